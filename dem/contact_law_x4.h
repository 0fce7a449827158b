#pragma once
// The contact law (contact_law.h) of four contacts at once, each in a lane of four_lanes.h's
// vectors: the kinematics at the force point, the contact length and the paper's forces (eqs.
// A.1, A.2), performed in the same order as the scalar functions, so that every lane gives their
// bits. The DEM's pair loop gathers a chunk's touching pairs four at a time into these lanes.
#include "dem/contact_law.h"
#include "dem/four_lanes.h"

namespace pilelab::dem {

/// Four contacts, in the frame of each pair (a, b): the overlap, the two bodies' motion, and
/// the spring the contact carried from the last step.
struct ContactLanes {
  Double4 area, chord;                  ///< overlap area [m^2] and contact-line length [m]
  Double4 point_x, point_y;             ///< force point [m]
  Double4 centroid_shift;               ///< Overlap::centroid_shift [m], for the caller that places the force point
  Double4 normal_x, normal_y;           ///< unit normal from a to b
  Double4 centre_a_x, centre_a_y, centre_b_x, centre_b_y;  ///< centroids [m]
  Double4 velocity_a_x, velocity_a_y, spin_a;  ///< a's velocity [m/s] and angular velocity [rad/s]
  Double4 velocity_b_x, velocity_b_y, spin_b;
  Double4 inverse_mass_a, inverse_mass_b;        ///< [1/kg], 0 for a wall
  Double4 inverse_inertia_a, inverse_inertia_b;  ///< [1/(kg m^2)], 0 for a wall
  Double4 lever_floor_a, lever_floor_b;  ///< half each body's inner radius [m]: the levers' floor
  Mask4 a_has_no_lever;                  ///< a is a flat wall, whose lever is infinite (World's contact law)
  /// The last step's spring force [N] and normal, 0 for a contact that did not touch then.
  Double4 old_spring, old_normal_x, old_normal_y;
};

/// What the law gives each lane: the forces in the contact's frame, the spring to keep, the force
/// on b in the world frame and the torques of the pair's forces about each body's centroid.
struct ContactLaneForces {
  Double4 normal, tangential, spring;  ///< [N], as ContactForce
  Double4 force_x, force_y;            ///< on b; on a the opposite [N]
  Double4 torque_a, torque_b;          ///< [N m]
};

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
/// The law of the four lanes' contacts with step dt [s], inlined into a caller compiled for its
/// own instruction set.
[[gnu::always_inline]] inline void contact_law_lanes(const ContactParameters& law, double dt, const ContactLanes& in, ContactLaneForces& out) {
  // The kinematics at the force point: levers r_a, r_b and the velocity of a relative to b.
  const Double4 nx = in.normal_x, ny = in.normal_y;
  const Double4 rax = in.point_x - in.centre_a_x, ray = in.point_y - in.centre_a_y;
  const Double4 rbx = in.point_x - in.centre_b_x, rby = in.point_y - in.centre_b_y;
  const Double4 uax = in.velocity_a_x + -in.spin_a * ray, uay = in.velocity_a_y + in.spin_a * rax;
  const Double4 ubx = in.velocity_b_x + -in.spin_b * rby, uby = in.velocity_b_y + in.spin_b * rbx;
  const Double4 dux = uax - ubx, duy = uay - uby;
  const Double4 ra2 = rax * rax + ray * ray, rb2 = rbx * rbx + rby * rby;
  const Double4 infinite = {INFINITY, INFINITY, INFINITY, INFINITY};
  const Double4 lever_a = in.a_has_no_lever ? infinite : lane_max(lane_sqrt(ra2), in.lever_floor_a);
  const Double4 lever_b = lane_max(lane_sqrt(rb2), in.lever_floor_b);
  const Double4 approach_speed = nx * dux + ny * duy;
  const Double4 slip_speed = -ny * dux + nx * duy;
  const Double4 inverse_masses = in.inverse_mass_a + in.inverse_mass_b;
  const Double4 normal_mass = 1.0 / inverse_masses;
  const Double4 tangential_mass = 1.0 / (inverse_masses + ra2 * in.inverse_inertia_a + rb2 * in.inverse_inertia_b);

  // contact_length: an infinite lever leaves the other one.
  const Double4 harmonic = lane_isinf(lever_a)   ? lever_b
                           : lane_isinf(lever_b) ? lever_a
                                                 : lever_a * lever_b / (lever_a + lever_b);
  const Double4 l = law.contact_length == ContactLength::book ? 4.0 * harmonic : harmonic;
  // The spring keeps its projection on the turned tangent; a jump of more than 60 degrees
  // starts it afresh.
  const Double4 turn = in.old_normal_x * nx + in.old_normal_y * ny;
  const Double4 zero = {0.0, 0.0, 0.0, 0.0};
  const Double4 spring = turn > 0.5 ? turn * in.old_spring : zero;

  // contact_force: A.1, elastic part and damping, never attractive.
  const double E = law.youngs_modulus;
  const Double4 repulsive = E * in.area / l;
  const Double4 d_eff_rate = in.chord * approach_speed / l;
  const Double4 damping = law.damping_gamma * d_eff_rate * lane_sqrt(E * normal_mass);
  const Double4 normal = repulsive + lane_max(damping, -repulsive);
  // A.2 where there is friction and a compressive normal force: the Cundall-Strack spring plus
  // the viscous term, capped at mu F_n.
  const double k_t = law.tangential_stiffness_ratio * E;
  const Double4 viscous = lane_sqrt(k_t * tangential_mass) * slip_speed;
  const Double4 stretched = spring + k_t * slip_speed * dt;
  const Double4 trial = stretched + viscous;
  const Double4 cap = law.friction_mu * normal;
  const Mask4 sticks = lane_abs(trial) <= cap;
  const Double4 sliding = lane_copysign(cap, trial);
  const Double4 kept = law.tangential_history == TangentialHistory::total ? trial : stretched;
  const Mask4 no_friction = law.friction_mu == 0.0 ? ~Mask4{} : (normal <= 0.0);
  const Double4 tangential = no_friction ? zero : sticks ? trial : sliding;
  out.normal = normal;
  out.tangential = tangential;
  out.spring = no_friction ? zero : sticks ? kept : sliding;

  // The force on b, normal n + tangential t with t = perp(n), and its torques.
  const Double4 fx = normal * nx + tangential * -ny, fy = normal * ny + tangential * nx;
  out.force_x = fx;
  out.force_y = fy;
  out.torque_b = rbx * fy - rby * fx;
  out.torque_a = -(rax * fy - ray * fx);
}
#pragma GCC diagnostic pop

/// contact_law_lanes as a function of its own, cloned for AVX2 and SSE2 (four_lanes.h): the
/// entry point of the tests that compare every lane with the scalar law. The pair loop inlines
/// contact_law_lanes instead.
void contact_law_x4(const ContactParameters& law, double dt, const ContactLanes& in, ContactLaneForces& out);

}  // namespace pilelab::dem
