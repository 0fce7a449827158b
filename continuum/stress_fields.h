#pragma once
// Stress measures shared by both models' outputs. Stresses are tension positive in the solvers
// and in the VTU stress_* fields (as coarse/'s fields), compressive positive in the derived
// measures (pressure, principal stresses) and in profiles.csv (as the paper plots them).
// N/m throughout (2D: force per length).
#include <string>

#include <deal.II/base/symmetric_tensor.h>

namespace pilelab::continuum {

/// A 2D stress, compressive positive: p = -sigma.
struct Stress2 {
  double xx = 0, yy = 0, xy = 0;
  static Stress2 from_tension_positive(const dealii::SymmetricTensor<2, 2>& sigma) {
    return {-sigma[0][0], -sigma[1][1], -sigma[0][1]};
  }
};

/// Principal values and axes of a compressive-positive stress.
struct Principal {
  double major = 0;           ///< s1, the larger principal value (most compressive)
  double minor = 0;           ///< s2 <= s1
  double orientation_deg = 0;  ///< s1's axis from the horizontal, counter-clockwise, in [0, 180): 90 vertical
  double anisotropy = 0;       ///< (s1 - s2) / (|s1| + |s2|) (common/principal_axes.h); 0 where unstressed
};

/// zero_scale: a stress below which |s1| + |s2| counts as zero (e.g. 1e-9 rho g h), so that the
/// stress-free surface gives anisotropy 0 rather than 0/0.
Principal principal_stress(const Stress2& p, double zero_scale);

}  // namespace pilelab::continuum

#include <functional>
#include <deal.II/numerics/data_postprocessor.h>

namespace pilelab::continuum {

/// Turns a model's stress at each output point into the named fields of docs/FORMAT.md, with
/// the names and signs of coarse/'s fields.vtu: stress_xx/yy/xy (N/m, tension positive),
/// pressure (N/m, compression positive), principal_stress_major/minor (N/m, compressive),
/// stress_anisotropy, stress_orientation_deg, and sigma_yy_over_rho_g_h (compression positive).
class StressPostprocessor : public dealii::DataPostprocessor<2> {
 public:
  /// stress(inputs, q): the compressive-positive stress at output point q.
  using StressAt = std::function<Stress2(const dealii::DataPostprocessorInputs::Vector<2>&, unsigned)>;
  StressPostprocessor(StressAt stress, dealii::UpdateFlags needed, double rho_g_h);

  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<2>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override;
  std::vector<std::string> get_names() const override;
  dealii::UpdateFlags get_needed_update_flags() const override { return needed_; }

 private:
  StressAt stress_;
  dealii::UpdateFlags needed_;
  double rho_g_h_;
};

}  // namespace pilelab::continuum
