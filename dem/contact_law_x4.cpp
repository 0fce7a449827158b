#include "dem/contact_law_x4.h"

namespace pilelab::dem {

// AVX2 where the processor has it, SSE2 otherwise: the same operations, the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void contact_law_x4(const ContactParameters& law, double dt, const ContactLanes& in, ContactLaneForces& out) {
  // The kinematics at the force point: levers r_a, r_b and the velocity of a relative to b.
  const Double4 nx = in.normal_x, ny = in.normal_y;
  const Double4 rax = in.point_x - in.centre_a_x, ray = in.point_y - in.centre_a_y;
  const Double4 rbx = in.point_x - in.centre_b_x, rby = in.point_y - in.centre_b_y;
  const Double4 uax = in.velocity_a_x + -in.spin_a * ray, uay = in.velocity_a_y + in.spin_a * rax;
  const Double4 ubx = in.velocity_b_x + -in.spin_b * rby, uby = in.velocity_b_y + in.spin_b * rbx;
  const Double4 dux = uax - ubx, duy = uay - uby;
  const Double4 ra2 = rax * rax + ray * ray, rb2 = rbx * rbx + rby * rby;
  const Double4 infinite = {INFINITY, INFINITY, INFINITY, INFINITY};
  const Double4 lever_a = in.a_is_wall ? infinite : lane_max(lane_sqrt(ra2), in.lever_floor_a);
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

}  // namespace pilelab::dem
