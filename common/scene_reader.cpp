#include "common/scene_reader.h"

#include <cmath>
#include <set>
#include <sstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/scene_presets.h"

namespace pilelab {

std::string Range::describe() const {
  std::ostringstream s;
  s.precision(10);
  const bool lo_inf = std::isinf(lo), hi_inf = std::isinf(hi);
  if (!lo_inf && !hi_inf) s << lo << (lo_open ? " < " : " <= ") << "value <= " << hi;
  else if (!lo_inf) s << "value " << (lo_open ? "> " : ">= ") << lo;
  else if (!hi_inf) s << "value <= " << hi;
  else s << "any finite number";
  return s.str();
}

namespace {
// Copies into `into` every key of `from` that `into` lacks, table by table.
void fill_missing(toml::table& into, const toml::table& from) {
  for (const auto& [key, value] : from) {
    toml::node* mine = into.get(key);
    if (!mine) {
      into.insert(key, value);
    } else if (mine->is_table() && value.is_table()) {
      fill_missing(*mine->as_table(), *value.as_table());
    }
  }
}
}  // namespace

SceneReader::SceneReader(const std::string& text, std::string source)
    : text_(text), source_(std::move(source)) {
  try {
    root_ = toml::parse(text_, source_);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << source_ << ":" << e.source().begin.line << ":" << e.source().begin.column
      << ": not valid TOML: " << e.description();
    throw InputError(s.str());
  }
  apply_preset();
}

// [scene] preset: its keys fill in what the scene leaves out, in the top-level tables the scene
// has (so that a preset never adds a stage to a run).
void SceneReader::apply_preset() {
  asked_.insert("scene.preset");
  if (!has("scene.preset")) return;
  std::vector<std::string> names;
  for (const auto& [name, _] : scene_presets()) names.push_back(name);
  const std::string preset = get_choice("scene.preset", "", names);
  for (const auto& [name, text] : scene_presets()) {
    if (name != preset) continue;
    const toml::table defaults = toml::parse(text, "preset " + name);
    for (const auto& [table, value] : defaults) {
      toml::node* mine = root_.get(table);
      if (mine && mine->is_table() && value.is_table()) fill_missing(*mine->as_table(), *value.as_table());
    }
  }
}

SceneReader SceneReader::from_file(const std::string& path) {
  return SceneReader(read_text_file(path), path);
}

const toml::node* SceneReader::find(std::string_view key) const {
  return root_.at_path(key).node();
}

bool SceneReader::has(std::string_view key) const { return find(key) != nullptr; }

void SceneReader::fail(std::string_view key, const std::string& what) const {
  throw InputError(source_ + ": " + std::string(key) + ": " + what);
}

double SceneReader::get_double(std::string_view key, double fallback, Range range) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  double v;
  if (auto d = n->value_exact<double>()) v = *d;
  else if (auto i = n->value_exact<std::int64_t>()) v = static_cast<double>(*i);
  else fail(key, "expected a number");
  if (!std::isfinite(v)) fail(key, "expected a finite number");
  if (!range.contains(v)) {
    std::ostringstream s;
    s.precision(10);
    s << v << " is out of range: expected " << range.describe();
    fail(key, s.str());
  }
  return v;
}

double SceneReader::require_double(std::string_view key, Range range) {
  if (!find(key)) {
    asked_.insert(std::string(key));
    fail(key, "missing: a number with " + range.describe() + " is required");
  }
  return get_double(key, 0.0, range);
}

std::int64_t SceneReader::get_int(std::string_view key, std::int64_t fallback, std::int64_t lo,
                                  std::int64_t hi) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  auto i = n->value_exact<std::int64_t>();
  if (!i)
    fail(key, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                  (n->is_floating_point() ? " written without a decimal point or exponent" : ""));
  if (*i < lo || *i > hi)
    fail(key, std::to_string(*i) + " is out of range: expected " + std::to_string(lo) +
                  " <= value <= " + std::to_string(hi));
  return *i;
}

bool SceneReader::get_bool(std::string_view key, bool fallback) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  auto b = n->value_exact<bool>();
  if (!b) fail(key, "expected true or false");
  return *b;
}

std::string SceneReader::get_string(std::string_view key, const std::string& fallback) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  auto s = n->value_exact<std::string>();
  if (!s) fail(key, "expected a string");
  return *s;
}

std::string SceneReader::get_choice(std::string_view key, const std::string& fallback,
                                    const std::vector<std::string>& choices) {
  const std::string v = get_string(key, fallback);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  fail(key, "\"" + v + "\" is not one of " + list);
}

std::vector<double> SceneReader::get_double_list(std::string_view key,
                                                 const std::vector<double>& fallback, Range range) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected an array of numbers");
  std::vector<double> out;
  for (const auto& e : *a) {
    double v;
    if (auto d = e.value_exact<double>()) v = *d;
    else if (auto i = e.value_exact<std::int64_t>()) v = static_cast<double>(*i);
    else fail(key, "expected an array of numbers");
    if (!std::isfinite(v) || !range.contains(v)) {
      std::ostringstream s;
      s << "element " << v << " is out of range: expected " << range.describe();
      fail(key, s.str());
    }
    out.push_back(v);
  }
  return out;
}

std::vector<std::int64_t> SceneReader::get_int_list(std::string_view key, const std::vector<std::int64_t>& fallback,
                                                    std::int64_t lo, std::int64_t hi) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  const std::string expected = "an array of integers from " + std::to_string(lo) + " to " + std::to_string(hi);
  if (!a) fail(key, "expected " + expected);
  std::vector<std::int64_t> out;
  for (const auto& e : *a) {
    const auto i = e.value_exact<std::int64_t>();
    if (!i) fail(key, "expected " + expected);
    if (*i < lo || *i > hi) fail(key, "element " + std::to_string(*i) + " is out of range: expected " + expected);
    out.push_back(*i);
  }
  return out;
}

std::vector<std::string> SceneReader::get_string_list(std::string_view key,
                                                      const std::vector<std::string>& fallback) {
  asked_.insert(std::string(key));
  const toml::node* n = find(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "expected an array of strings");
  std::vector<std::string> out;
  for (const auto& e : *a) {
    auto v = e.value_exact<std::string>();
    if (!v) fail(key, "expected an array of strings");
    out.push_back(*v);
  }
  return out;
}

std::string SceneReader::table_text(std::string_view table) const {
  const toml::node* n = root_.get(table);
  if (!n || !n->is_table()) return "";
  std::ostringstream out;
  out << *n->as_table();
  return out.str();
}

namespace {
// The dotted paths of every value in t, and of every empty table (which holds no value to
// catch a misspelt table name by).
void collect_leaves(const toml::table& t, const std::string& prefix, std::vector<std::string>& out,
                    std::vector<std::string>& empty_tables) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table()) {
      if (sub->empty()) empty_tables.push_back(path);
      collect_leaves(*sub, path, out, empty_tables);
    } else {
      out.push_back(path);
    }
  }
}
}  // namespace

void SceneReader::reject_unknown(const std::vector<std::string>& tables_to_check,
                                 const std::vector<std::string>& known_tables) const {
  for (const auto& [k, v] : root_) {
    const std::string name(k.str());
    bool known = false;
    for (const auto& t : known_tables) known = known || (t == name);
    if (!known) {
      std::string list;
      for (const auto& t : known_tables) list += (list.empty() ? "[" : "], [") + t;
      throw InputError(source_ + ": unknown top-level key or table '" + name + "' (known: " + list + "])");
    }
  }
  std::vector<std::string> leaves, empty_tables;
  collect_leaves(root_, "", leaves, empty_tables);
  // Whether this stage checks the top-level table a dotted path lies in.
  const auto checked_here = [&](const std::string& path) {
    const std::string top = path.substr(0, path.find('.'));
    for (const auto& t : tables_to_check)
      if (t == top) return true;
    return false;
  };
  for (const auto& table : empty_tables) {
    // A table is known if any key was asked for inside it; list the known tables beside it.
    bool known = false;
    std::set<std::string> siblings;
    const std::string parent = table.find('.') == std::string::npos ? "" : table.substr(0, table.rfind('.'));
    for (const auto& a : asked_) {
      known = known || a.rfind(table + ".", 0) == 0;
      if (!parent.empty() && a.rfind(parent + ".", 0) == 0) {
        const std::string rest = a.substr(parent.size() + 1);
        if (rest.find('.') != std::string::npos) siblings.insert(parent + "." + rest.substr(0, rest.find('.')));
      }
    }
    if (!checked_here(table) || known) continue;
    std::string list;
    for (const auto& t : siblings) list += (list.empty() ? "" : "], [") + t;
    throw InputError(source_ + ": unknown table [" + table + "]" +
                     (list.empty() ? std::string() : " (known tables: [" + list + "])"));
  }
  for (const auto& leaf : leaves) {
    if (!checked_here(leaf) || asked_.count(leaf)) continue;
    // Name the keys that would have been accepted in the same table, to make typos obvious.
    const std::string table = leaf.substr(0, leaf.rfind('.'));
    std::string known;
    for (const auto& a : asked_)
      if (a.rfind(table + ".", 0) == 0 && a.find('.', table.size() + 1) == std::string::npos)
        known += (known.empty() ? "" : ", ") + a.substr(table.size() + 1);
    throw InputError(source_ + ": unknown key '" + leaf + "'" +
                     (known.empty() ? std::string(" (no such table)") : " (known keys in [" + table + "]: " + known + ")"));
  }
}

}  // namespace pilelab
