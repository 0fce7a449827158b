#include "common/ensemble.h"

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "common/error.h"

namespace pilelab {

EnsembleSpec read_ensemble_scene(SceneReader& r) {
  EnsembleSpec e;
  constexpr std::int64_t max_seed = INT64_MAX, max_members = 100000;
  const bool listed = r.has("ensemble.seeds"), counted = r.has("ensemble.count");
  if (listed && counted)
    throw InputError(r.source() + ": ensemble: give either seeds = [...] or count = N (with first_seed), not both");
  if (!listed && !counted) {
    if (r.has("ensemble"))
      throw InputError(r.source() + ": [ensemble] needs seeds = [...] or count = N (with first_seed, default 1)");
    return e;
  }
  if (listed) {
    e.seeds = r.get_int_list("ensemble.seeds", {}, 0, max_seed);
    if (e.seeds.empty()) throw InputError(r.source() + ": ensemble.seeds: expected at least one seed");
    if (r.has("ensemble.first_seed"))
      throw InputError(r.source() + ": ensemble.first_seed goes with ensemble.count, not with ensemble.seeds");
  } else {
    const std::int64_t count = r.get_int("ensemble.count", 1, 1, max_members);
    const std::int64_t first = r.get_int("ensemble.first_seed", 1, 0, max_seed - count);
    for (std::int64_t k = 0; k < count; ++k) e.seeds.push_back(first + k);
  }
  std::set<std::int64_t> seen;
  for (std::int64_t s : e.seeds)
    if (!seen.insert(s).second)
      throw InputError(r.source() + ": ensemble.seeds: seed " + std::to_string(s) + " is listed twice (each member needs its own)");
  return e;
}

std::string member_directory(const std::string& out_dir, std::int64_t seed) {
  return (std::filesystem::path(out_dir) / "members" / std::to_string(seed)).string();
}

std::string member_scene_text(const std::string& scene_path, std::int64_t seed) {
  toml::table root;
  try {
    root = toml::parse_file(scene_path);
  } catch (const toml::parse_error& e) {
    throw InputError(scene_path + ": " + std::string(e.description()));
  }
  toml::table member;
  if (const toml::table* scene = root["scene"].as_table()) member.insert("scene", *scene);
  toml::table dem;
  if (const toml::table* d = root["dem"].as_table()) dem = *d;
  dem.insert_or_assign("seed", seed);
  member.insert("dem", dem);
  std::ostringstream text;
  text << "# One member of the ensemble of " << std::filesystem::path(scene_path).filename().string()
       << ": its [scene] and [dem] tables with this member's seed.\n"
       << member << "\n";
  return text.str();
}

SampleStatistics sample_statistics(const std::vector<double>& values) {
  SampleStatistics s;
  double sum = 0.0;
  for (double v : values) {
    if (!std::isfinite(v)) {
      ++s.missing;
      continue;
    }
    sum += v;
    ++s.count;
  }
  if (s.count == 0) {
    s.mean = s.standard_deviation = s.standard_error = NAN;
    return s;
  }
  s.mean = sum / s.count;
  double squares = 0.0;
  for (double v : values)
    if (std::isfinite(v)) squares += (v - s.mean) * (v - s.mean);
  s.standard_deviation = s.count > 1 ? std::sqrt(squares / (s.count - 1)) : NAN;
  s.standard_error = s.count > 1 ? s.standard_deviation / std::sqrt(static_cast<double>(s.count)) : NAN;
  return s;
}

}  // namespace pilelab
