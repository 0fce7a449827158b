// Isotropic linear elasticity as a model of the solve stage: its scene table
// [continuum.elastic] and its solve (continuum/elastic_problem.h has the method).
#include "common/error.h"
#include "continuum/elastic_problem.h"
#include "continuum/model_context.h"

namespace pilelab::continuum {

namespace {

// The moduli as Young's modulus and Poisson's ratio, or as Lame's two constants.
void read_moduli(ModelTable& t, ElasticSettings& e) {
  SceneReader& r = t.reader();
  const std::string& src = t.source();
  if (t.has("lame_lambda_N_per_m") || t.has("shear_modulus_N_per_m")) {
    if (t.has("youngs_modulus_N_per_m") || t.has("poisson_ratio"))
      throw InputError(src + ": [continuum.elastic]: give either youngs_modulus_N_per_m and poisson_ratio, "
                             "or lame_lambda_N_per_m and shear_modulus_N_per_m, not both pairs");
    const double lambda = r.require_double(t.key("lame_lambda_N_per_m"), Range::at_least(0.0));
    const double mu = r.require_double(t.key("shear_modulus_N_per_m"), Range::positive());
    e.material = IsotropicMaterial::from_lame(lambda, mu);
    return;
  }
  IsotropicMaterial& m = e.material;
  m.youngs_modulus_N_per_m = r.get_double(t.key("youngs_modulus_N_per_m"), m.youngs_modulus_N_per_m, Range::positive());
  m.poisson_ratio = r.get_double(t.key("poisson_ratio"), m.poisson_ratio, Range{});
  if (!(m.poisson_ratio < 0.5))
    throw InputError(src + ": continuum.elastic.poisson_ratio: " + std::to_string(m.poisson_ratio) +
                     " is not allowed: expected -1 < nu < 0.5 (nu = 0.5 is incompressible, which "
                     "the displacement formulation cannot represent)");
  if (!(m.poisson_ratio > -1.0)) throw InputError(src + ": continuum.elastic.poisson_ratio: expected -1 < nu < 0.5");
}

std::shared_ptr<const ModelSettings> read(ModelTable& t) {
  auto e = std::make_shared<ElasticSettings>();
  SceneReader& r = t.reader();
  read_moduli(t, *e);
  e->plane = r.get_choice(t.key("plane"), "strain", {"strain", "stress"}) == "stress" ? ElasticSettings::Plane::stress
                                                                                   : ElasticSettings::Plane::strain;
  e->base = r.get_choice(t.key("base"), "rough", {"rough", "smooth"}) == "smooth" ? ElasticSettings::Base::smooth
                                                                                : ElasticSettings::Base::rough;
  e->degree = static_cast<int>(r.get_int(t.key("degree"), e->degree, 1, 2));
  e->gravity_change = r.get_double(t.key("gravity_change"), e->gravity_change, Range{-1.0, 1.0, false});
  e->solver = read_solver(t, e->solver);
  return e;
}

// Isotropic elasticity under gravity, and the gravity change its displacements are for.
nlohmann::json solve(const ModelSettings& settings, ModelContext& c) {
  const auto& e = dynamic_cast<const ElasticSettings&>(settings);
  ElasticProblem problem(c.tria, e, c.settings.density_kg_per_m2, c.settings.gravity_m_per_s2);
  nlohmann::json j = solve_model(problem, "elastic", e.solver, c);
  j["degree"] = e.degree;
  j["plane"] = e.plane == ElasticSettings::Plane::strain ? "strain" : "stress";
  j["base"] = e.base == ElasticSettings::Base::rough ? "rough" : "smooth";
  j["base_reaction_over_weight"] = problem.result().base_reaction_N / problem.result().weight;
  j["youngs_modulus_N_per_m"] = e.material.youngs_modulus_N_per_m;
  j["poisson_ratio"] = e.material.poisson_ratio;
  j["gravity_change"] = e.gravity_change;
  // Its displacement and strain are those of this change of g: compare scales them to the DEM's.
  c.fields.back().attributes["gravity_change"] = e.gravity_change;
  return j;
}

}  // namespace

extern const ModelDefinition elastic_model = {"elastic", "isotropic linear elasticity under gravity (plane strain or stress)",
                                              read, solve};

}  // namespace pilelab::continuum
