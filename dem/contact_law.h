#pragma once
// The contact law of the paper (Appendix A): from the overlap of two bodies and their motion,
// the normal force (elastic R = E A / l plus damping, never attractive) and the Cundall-Strack
// tangential force (spring 2E/7 plus viscous term, capped by Coulomb's mu * F_n). Pure
// functions of plain values: the caller owns the spring history.

#include <algorithm>
#include <cmath>

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

/// Where the normal force acts along the contact line (paper, eq. A.1 and Appendix A).
enum class ForcePoint {
  /// Where the overlap's centroid projects onto the contact line. A force E A / l (fixed l) is
  /// then the gradient of (E / l) times the overlap's first moment of depth, so it stores and
  /// returns energy: a lone grain rocking on its corners comes to rest (docs/DEM.md).
  area_centroid,
  /// The chord's midpoint, as Appendix A places it. The force is then not conservative where the
  /// overlap is not symmetric (a corner pressed into an edge): a grain rocking between two
  /// corners gains energy and never settles.
  chord_midpoint,
};

struct ContactParameters {
  double youngs_modulus = 1e7;           ///< E [N/m] (2D: force per unit depth per unit strain)
  double damping_gamma = 0.75;           ///< gamma, dimensionless
  double friction_mu = 0.54;             ///< Coulomb coefficient, static = dynamic
  double tangential_stiffness_ratio = 2.0 / 7.0;  ///< k_t / E (paper: 2/7)
  ContactLength contact_length = ContactLength::paper;
  TangentialHistory tangential_history = TangentialHistory::spring;
  ForcePoint force_point = ForcePoint::area_centroid;
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

// Both inline: the DEM evaluates them for every contact of every step.

/// l from the lever arms (an infinite lever stands for a wall). The caller floors each lever at
/// half the body's inner radius, so that a pathological deep overlap with the force point at a
/// centroid cannot divide by 0.
inline double contact_length(const ContactParameters& p, double lever_a, double lever_b) {
  // An infinite lever (a wall) leaves the other one: r_a r_b / (r_a + r_b) -> r_b.
  const double harmonic = std::isinf(lever_a) ? lever_b
                          : std::isinf(lever_b) ? lever_a
                                                : lever_a * lever_b / (lever_a + lever_b);
  return p.contact_length == ContactLength::book ? 4.0 * harmonic : harmonic;
}

/// One step of the contact law. spring is the tangential spring force carried from the last
/// step (0 for a new contact); dt advances it.
inline ContactForce contact_force(const ContactParameters& p, const ContactKinematics& k, double l,
                                  double spring, double dt) {
  ContactForce f{0.0, 0.0, 0.0};
  // A.1: elastic part from the effective depth d_eff = A / l.
  const double repulsive = p.youngs_modulus * k.area / l;
  // A.1: damping proportional to d(d_eff)/dt = (dA/dt) / l. For rigid motions dA/dt is exactly
  // chord * approach speed (see convex_overlap.h), which we use instead of a finite difference.
  const double d_eff_rate = k.chord * k.approach_speed / l;
  const double damping = p.damping_gamma * d_eff_rate * std::sqrt(p.youngs_modulus * k.normal_mass);
  // The cut-off at -R: damping may cancel the elastic force but never make it attractive.
  f.normal = repulsive + std::max(damping, -repulsive);

  if (p.friction_mu == 0.0 || f.normal <= 0.0) return f;  // no friction, no history
  // A.2: Cundall-Strack spring, advanced by the slip, plus a viscous term; the total is capped
  // at mu F_n. The spring force opposes slip of a relative to b, i.e. acts along -t on a.
  const double k_t = p.tangential_stiffness_ratio * p.youngs_modulus;
  const double viscous = std::sqrt(k_t * k.tangential_mass) * k.slip_speed;
  const double stretched = spring + k_t * k.slip_speed * dt;
  const double trial = stretched + viscous;
  const double cap = p.friction_mu * f.normal;
  if (std::abs(trial) <= cap) {
    f.tangential = trial;
    f.spring = p.tangential_history == TangentialHistory::total ? trial : stretched;
  } else {
    // Sliding: the spring stops stretching and holds the Coulomb value.
    f.tangential = std::copysign(cap, trial);
    f.spring = f.tangential;
  }
  return f;
}

}  // namespace pilelab::dem
