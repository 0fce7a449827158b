#pragma once
// Reads a scene file (TOML) and keeps track of every key a stage asked for, so that a key
// nobody reads, usually a typo, is an error that names the key and the file instead of being
// silently ignored. Every numeric read carries its allowed range; a value outside it is an
// error that states the range.
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace pilelab {

/// A closed interval [lo, hi] for numeric scene values.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  ///< true: lo itself is not allowed
  static Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true}; }
  static Range closed(double lo, double hi) { return {lo, hi, false}; }
  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
  std::string describe() const;
};

class SceneReader {
 public:
  /// Parses TOML text; source names the file in every message.
  SceneReader(const std::string& text, std::string source);
  static SceneReader from_file(const std::string& path);

  const std::string& text() const { return text_; }
  const std::string& source() const { return source_; }

  /// Keys are dotted paths, e.g. "dem.contact.friction_mu".
  bool has(std::string_view key) const;
  /// A top-level table in canonical TOML (empty if the scene has no such table): what a stage
  /// depends on, for deciding whether its outputs are stale.
  std::string table_text(std::string_view table) const;
  double get_double(std::string_view key, double fallback, Range range);
  double require_double(std::string_view key, Range range);
  std::int64_t get_int(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi);
  bool get_bool(std::string_view key, bool fallback);
  std::string get_string(std::string_view key, const std::string& fallback);
  std::string get_choice(std::string_view key, const std::string& fallback,
                         const std::vector<std::string>& choices);
  std::vector<double> get_double_list(std::string_view key, const std::vector<double>& fallback,
                                      Range range);
  std::vector<std::string> get_string_list(std::string_view key, const std::vector<std::string>& fallback);
  std::vector<std::int64_t> get_int_list(std::string_view key, const std::vector<std::int64_t>& fallback,
                                         std::int64_t lo, std::int64_t hi);

  /// Throws InputError for any key under the given top-level tables that no get_* call asked
  /// for, and for any top-level table not in known_tables.
  void reject_unknown(const std::vector<std::string>& tables_to_check,
                      const std::vector<std::string>& known_tables) const;

 private:
  void apply_preset();
  const toml::node* find(std::string_view key) const;
  [[noreturn]] void fail(std::string_view key, const std::string& what) const;
  std::string text_;
  std::string source_;
  toml::table root_;
  std::set<std::string> asked_;
};

}  // namespace pilelab
