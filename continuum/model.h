#pragma once
// A continuum model as the solve stage sees it: a name, a reader for its scene table
// [continuum.<name>], and a solve on the pile. Each model is defined in a file of its own under
// continuum/models/ as a `const ModelDefinition <name>_model` and listed by one line in
// model_registry.cpp; settings.cpp, solve.cpp and compare/ know no model by name. This header
// is deal.II-free, so that the command-line front end (`pilelab check`) reads every model's
// table without compiling deal.II.
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "common/scene_reader.h"

namespace pilelab::continuum {

/// A model's settings, as its reader makes them; each model derives its own.
struct ModelSettings {
  virtual ~ModelSettings() = default;
};

/// One model's scene table, [continuum.<name>]: hands out the full key names and records every
/// key asked for, so that settings.cpp can refuse a key no model reads.
class ModelTable {
 public:
  ModelTable(SceneReader& reader, std::string model, bool listed, std::set<std::string>& asked)
      : reader_(reader), table_("continuum." + model), listed_(listed), asked_(asked) {}
  /// "continuum.<name>.<k>", recorded as known.
  const std::string& key(const std::string& k) { return *asked_.insert(table_ + "." + k).first; }
  bool has(const std::string& k) const { return reader_.has(table_ + "." + k); }
  SceneReader& reader() { return reader_; }
  const std::string& source() const { return reader_.source(); }
  const std::string& table() const { return table_; }
  /// Whether continuum.models lists the model (a model may require keys only then).
  bool listed() const { return listed_; }

 private:
  SceneReader& reader_;
  std::string table_;
  bool listed_;
  std::set<std::string>& asked_;
};

struct ModelContext;  // the pile, its mesh and the shared outputs (continuum/model_context.h, deal.II)

struct ModelDefinition {
  const char* name;         ///< its name in continuum.models and its table [continuum.<name>]
  const char* description;  ///< one line, for errors and docs
  /// Reads [continuum.<name>] (defaults for keys it lacks); InputError naming the key.
  std::shared_ptr<const ModelSettings> (*read)(ModelTable& table);
  /// Solves the model on the context's pile, adds its fields and profiles to the context's
  /// outputs, and returns its section of the report (model_context.h: solve_model).
  nlohmann::json (*solve)(const ModelSettings& settings, ModelContext& context);
};

/// The registered models, in the order `pilelab solve` runs them (model_registry.cpp).
const std::vector<const ModelDefinition*>& model_definitions();
/// Their names, in that order.
std::vector<std::string> model_names();
/// The model of that name, or nullptr.
const ModelDefinition* find_model(const std::string& name);

}  // namespace pilelab::continuum
