#pragma once
// The contact law of the paper (Appendix A): from the overlap of two bodies and their motion,
// the normal force (elastic R = E A / l plus damping, never attractive) and the Cundall-Strack
// tangential force (spring 2E/7 plus viscous term, capped by Coulomb's mu * F_n). Pure
// functions of plain values: the caller owns the spring history.

namespace pilelab::dem {

/// How the contact length l in R = E A / l is formed from the distances r_i, r_j between the
/// body centroids and the force point.
enum class ContactLength {
  paper,  ///< l = r_i r_j / (r_i + r_j)   (paper, eq. A.1)
  book,   ///< l = 4 r_i r_j / (r_i + r_j) (Matuttis & Chen's code: l = 2r, the sum of the levers, for equal levers r)
};

/// What the Cundall-Strack history holds from one step to the next (paper, eq. A.2).
enum class TangentialHistory {
  spring,  ///< the spring alone; the viscous term is added afresh each step (stiffness k_t)
  total,   ///< the whole tangential force, viscous term included, as A.2 reads literally: the
           ///< viscous term then accumulates, a stiffness k_t + sqrt(k_t m)/dt that depends on dt
};

struct ContactParameters {
  double youngs_modulus = 1e7;           ///< E [N/m] (2D: force per unit depth per unit strain)
  double damping_gamma = 0.75;           ///< gamma, dimensionless
  double friction_mu = 0.54;             ///< Coulomb coefficient, static = dynamic
  double tangential_stiffness_ratio = 2.0 / 7.0;  ///< k_t / E (paper: 2/7)
  ContactLength contact_length = ContactLength::paper;
  TangentialHistory tangential_history = TangentialHistory::spring;
};

/// What the contact law needs to know of a contact, in the frame of the pair (a, b) with the
/// unit normal n pointing from a to b and the tangent t = n turned by +90 degrees.
struct ContactKinematics {
  double area;            ///< overlap area A [m^2]
  double chord;           ///< contact-line length [m]
  double lever_a;         ///< |force point - centroid of a| [m]
  double lever_b;         ///< |force point - centroid of b| [m]
  double approach_speed;  ///< n . (u_a - u_b) at the force point [m/s]; > 0 while approaching
  double slip_speed;      ///< t . (u_a - u_b) at the force point [m/s]
  double normal_mass;     ///< m_a m_b / (m_a + m_b) [kg] (paper's m_perp)
  double tangential_mass; ///< 1 / (1/m_a + 1/m_b + r_a^2/I_a + r_b^2/I_b) (paper's m_par)
};

struct ContactForce {
  double normal;      ///< F_n >= 0, pushes b along +n and a along -n [N]
  double tangential;  ///< F_t along +t on b and -t on a [N]
  double spring;      ///< the spring force to keep for the next step [N]
};

/// l from the lever arms (an infinite lever stands for a wall). The caller floors each lever at
/// half the body's inner radius, so that a pathological deep overlap with the force point at a
/// centroid cannot divide by 0.
double contact_length(const ContactParameters& p, double lever_a, double lever_b);

/// One step of the contact law. spring is the tangential spring force carried from the last
/// step (0 for a new contact); dt advances it.
ContactForce contact_force(const ContactParameters& p, const ContactKinematics& k, double length_l,
                           double spring, double dt);

}  // namespace pilelab::dem
