// The OSL model: its scene table [continuum.osl] (the two constants and the closure's numerical
// settings) and its solve (continuum/models/osl.h has the closure and its wedge solution).
#include "continuum/models/osl.h"

#include <cmath>

#include "common/error.h"
#include "continuum/model_context.h"

namespace pilelab::continuum {

namespace {

std::shared_ptr<const ModelSettings> read(ModelTable& t) {
  auto s = std::make_shared<OslSettings>();
  SceneReader& r = t.reader();
  // Both constants are the model: a scene that lists "osl" gives them (no default would be a
  // measurement; the FPA is eta = 1, mu = 2 tan(phi)).
  if (t.listed()) {
    s->eta = r.require_double(t.key("eta"), Range::positive());
    s->mu = r.require_double(t.key("mu"), Range{});
  } else {
    s->eta = r.get_double(t.key("eta"), s->eta, Range::positive());
    s->mu = r.get_double(t.key("mu"), s->mu, Range{});
  }
  if (!std::isfinite(s->eta) || !std::isfinite(s->mu))
    throw InputError(t.source() + ": [continuum.osl]: expected finite eta > 0 and mu");
  read_closure_settings(t, *s);
  return s;
}

nlohmann::json solve(const ModelSettings& settings, ModelContext& c) {
  const auto& s = dynamic_cast<const OslSettings&>(settings);
  OslProblem problem(c.tria, s, c.settings.density_kg_per_m2, c.settings.gravity_m_per_s2, c.pile.apex_x_m);
  nlohmann::json j = solve_model(problem, "osl", s.solver, c);
  j["eta"] = s.eta;
  j["mu"] = s.mu;
  j["reversed_shear_area_fraction"] = problem.result().reversed_shear_area_fraction;
  // A flank that is a characteristic (1 + mu tan(phi) - eta tan^2(phi) = 0) also shows as
  // missing weight.
  report_closure(s, problem.result(), "OSL", c, j);
  return j;
}

}  // namespace

extern const ModelDefinition osl_model = {
    "osl", "oriented stress linearity (Wittmer, Claudin, Cates & Bouchaud), least squares", read, solve};

}  // namespace pilelab::continuum
