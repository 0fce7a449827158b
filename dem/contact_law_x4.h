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
  Double4 normal_x, normal_y;           ///< unit normal from a to b
  Double4 centre_a_x, centre_a_y, centre_b_x, centre_b_y;  ///< centroids [m]
  Double4 velocity_a_x, velocity_a_y, spin_a;  ///< a's velocity [m/s] and angular velocity [rad/s]
  Double4 velocity_b_x, velocity_b_y, spin_b;
  Double4 inverse_mass_a, inverse_mass_b;        ///< [1/kg], 0 for a wall
  Double4 inverse_inertia_a, inverse_inertia_b;  ///< [1/(kg m^2)], 0 for a wall
  Double4 lever_floor_a, lever_floor_b;  ///< half each body's inner radius [m]: the levers' floor
  Mask4 a_is_wall;                       ///< a wall's lever is infinite (World's contact law)
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

/// The law of the four lanes' contacts with step dt [s].
void contact_law_x4(const ContactParameters& law, double dt, const ContactLanes& in, ContactLaneForces& out);

}  // namespace pilelab::dem
