#include "continuum/stress_fields.h"

#include <cmath>

namespace pilelab::continuum {

Principal principal_stress(const Stress2& p, double zero_scale) {
  // Eigenvalues of [[xx, xy], [xy, yy]]: mean +- radius of Mohr's circle.
  const double mean = 0.5 * (p.xx + p.yy);
  const double radius = std::hypot(0.5 * (p.xx - p.yy), p.xy);
  Principal out;
  out.major = mean + radius;
  out.minor = mean - radius;
  // The major axis makes the angle theta with x where tan(2 theta) = 2 xy / (xx - yy), on the
  // branch that maximises the normal stress: theta = atan2(2 xy, xx - yy) / 2 in (-90, 90],
  // then taken into [0, 180) (an axis, not a direction).
  out.orientation_deg = 0.5 * std::atan2(2.0 * p.xy, p.xx - p.yy) * 180.0 / M_PI;
  if (out.orientation_deg < 0.0) out.orientation_deg += 180.0;
  if (out.orientation_deg >= 180.0) out.orientation_deg -= 180.0;
  const double sum = std::abs(out.major + out.minor);
  out.anisotropy = sum > zero_scale ? (out.major - out.minor) / sum : 0.0;
  return out;
}

StressPostprocessor::StressPostprocessor(StressAt stress, dealii::UpdateFlags needed, double rho_g_h)
    : stress_(std::move(stress)), needed_(needed), rho_g_h_(rho_g_h) {}

std::vector<std::string> StressPostprocessor::get_names() const {
  return {"stress_xx",        "stress_yy",         "stress_xy",      "pressure", "principal_stress_major",
          "principal_stress_minor", "stress_anisotropy", "stress_orientation_deg", "sigma_yy_over_rho_g_h"};
}

void StressPostprocessor::evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<2>& inputs,
                                                std::vector<dealii::Vector<double>>& computed) const {
  for (unsigned q = 0; q < computed.size(); ++q) {
    const Stress2 p = stress_(inputs, q);
    const Principal pr = principal_stress(p, 1e-9 * rho_g_h_);
    dealii::Vector<double>& c = computed[q];
    c[0] = -p.xx;  // tension positive, as fields.vtu
    c[1] = -p.yy;
    c[2] = -p.xy;
    c[3] = 0.5 * (p.xx + p.yy);
    c[4] = pr.major;
    c[5] = pr.minor;
    c[6] = pr.anisotropy;
    c[7] = pr.orientation_deg;
    c[8] = p.yy / rho_g_h_;
  }
}

}  // namespace pilelab::continuum
