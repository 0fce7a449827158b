// The continuum models a scene may list (continuum.models), one line each, in the order
// `pilelab solve` runs them. A model is defined in continuum/models/<name>.cpp as a
// `const ModelDefinition <name>_model` (continuum/model.h).
#include "continuum/model.h"

namespace pilelab::continuum {

#define PILELAB_MODELS(X) \
  X(elastic)              \
  X(fpa)                  \
  X(osl)

#define PILELAB_DECLARE_MODEL(name) extern const ModelDefinition name##_model;
PILELAB_MODELS(PILELAB_DECLARE_MODEL)
#undef PILELAB_DECLARE_MODEL

const std::vector<const ModelDefinition*>& model_definitions() {
#define PILELAB_LIST_MODEL(name) &name##_model,
  static const std::vector<const ModelDefinition*> models = {PILELAB_MODELS(PILELAB_LIST_MODEL)};
#undef PILELAB_LIST_MODEL
  return models;
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (const ModelDefinition* m : model_definitions()) names.emplace_back(m->name);
  return names;
}

const ModelDefinition* find_model(const std::string& name) {
  for (const ModelDefinition* m : model_definitions())
    if (name == m->name) return m;
  return nullptr;
}

}  // namespace pilelab::continuum
