#include "continuum/stress_fields.h"

#include <cmath>

#include "common/principal_axes.h"

namespace pilelab::continuum {

Principal principal_stress(const Stress2& p, double zero_scale) {
  const PrincipalAxes axes = principal_axes(p.xx, p.yy, p.xy, zero_scale);
  return {axes.major, axes.minor, axes.orientation_deg, axes.anisotropy};
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
