#include "mesh/msh_check.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <vector>

#include "common/error.h"

namespace pilelab::mesh {

namespace {

// Nodes per element of the gmsh element types a 2D mesh may hold (points, lines, triangles,
// quadrangles, of order 1 and 2); others are refused.
int nodes_of_element_type(long type) {
  switch (type) {
    case 15: return 1;  // point
    case 1: return 2;   // 2-node line
    case 8: return 3;   // 3-node line
    case 2: return 3;   // 3-node triangle
    case 9: return 6;   // 6-node triangle
    case 3: return 4;   // 4-node quadrangle
    case 10: return 9;  // 9-node quadrangle
    case 16: return 8;  // 8-node quadrangle
    default: return -1;
  }
}

// Reads the file token by token, keeping the line number for messages.
class Tokens {
 public:
  explicit Tokens(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path + ": cannot open the mesh file (expected a gmsh .msh file)");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ": line " + std::to_string(line_) + ": " + what + " (expected a gmsh ASCII .msh file, format 4.1 or 2.2)");
  }
  std::string word() {
    std::string w;
    while (true) {
      const int c = in_.get();
      if (c == EOF) {
        if (w.empty()) fail("the file ends early");
        return w;
      }
      if (std::isspace(c)) {
        if (!w.empty()) {
          in_.unget();  // the line of a token is the line it is on
          return w;
        }
        if (c == '\n') ++line_;
        continue;
      }
      w.push_back(static_cast<char>(c));
      if (w.size() > 256) fail("a token longer than 256 characters");
    }
  }
  long integer(const char* what, long lo = std::numeric_limits<long>::min(), long hi = std::numeric_limits<long>::max()) {
    const std::string w = word();
    std::size_t used = 0;
    long v = 0;
    try {
      v = std::stol(w, &used);
    } catch (const std::exception&) {
      fail(std::string(what) + " '" + w + "' is not an integer");
    }
    if (used != w.size()) fail(std::string(what) + " '" + w + "' is not an integer");
    if (v < lo || v > hi) fail(std::string(what) + " " + w + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  double real(const char* what) {
    const std::string w = word();
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(w, &used);
    } catch (const std::exception&) {
      fail(std::string(what) + " '" + w + "' is not a number");
    }
    if (used != w.size() || !std::isfinite(v)) fail(std::string(what) + " '" + w + "' is not a finite number");
    return v;
  }
  // Skips to the line "$End<section>".
  void skip_section(const std::string& section) {
    for (std::string w = word(); w != "$End" + section; w = word()) {
    }
  }
  void expect(const std::string& w) {
    const std::string got = word();
    if (got != w) fail("'" + w + "' expected, found '" + got + "'");
  }
  bool at_end() {
    while (std::isspace(in_.peek())) {
      if (in_.get() == '\n') ++line_;
    }
    return in_.peek() == EOF;
  }

 private:
  std::string path_;
  std::ifstream in_;
  long line_ = 1;
};

// A bound on every count, far above any pile mesh: a damaged count must not make the check
// itself allocate or loop for ever.
constexpr long max_count = 100000000;

void check_nodes_41(Tokens& t, std::unordered_set<long>& tags) {
  const long blocks = t.integer("$Nodes: number of entity blocks", 0, max_count);
  const long count = t.integer("$Nodes: number of nodes", 0, max_count);
  const long min_tag = t.integer("$Nodes: smallest node tag", 0), max_tag = t.integer("$Nodes: largest node tag", 0);
  long seen = 0;
  for (long b = 0; b < blocks; ++b) {
    t.integer("$Nodes: entity dimension", 0, 3);
    t.integer("$Nodes: entity tag");
    const long parametric = t.integer("$Nodes: parametric flag", 0, 1);
    const long n = t.integer("$Nodes: nodes in the block", 0, count - seen);
    std::vector<long> block;
    for (long i = 0; i < n; ++i) {
      const long tag = t.integer("$Nodes: node tag", std::max(min_tag, 1L), max_tag);
      if (!tags.insert(tag).second) t.fail("$Nodes: node tag " + std::to_string(tag) + " is defined twice");
    }
    for (long i = 0; i < n; ++i)
      for (int c = 0; c < 3 + (parametric ? 1 : 0); ++c) t.real("$Nodes: coordinate");
    seen += n;
  }
  if (seen != count) t.fail("$Nodes: the blocks hold " + std::to_string(seen) + " nodes, the header says " + std::to_string(count));
  t.expect("$EndNodes");
}

void check_elements_41(Tokens& t, const std::unordered_set<long>& nodes) {
  const long blocks = t.integer("$Elements: number of entity blocks", 0, max_count);
  const long count = t.integer("$Elements: number of elements", 0, max_count);
  t.integer("$Elements: smallest element tag", 0);
  t.integer("$Elements: largest element tag", 0);
  long seen = 0;
  for (long b = 0; b < blocks; ++b) {
    t.integer("$Elements: entity dimension", 0, 3);
    t.integer("$Elements: entity tag");
    const long type = t.integer("$Elements: element type");
    const int per = nodes_of_element_type(type);
    if (per < 0) t.fail("$Elements: element type " + std::to_string(type) + " is not one of a 2D mesh's");
    const long n = t.integer("$Elements: elements in the block", 0, count - seen);
    for (long e = 0; e < n; ++e) {
      t.integer("$Elements: element tag", 1);
      for (int k = 0; k < per; ++k) {
        const long node = t.integer("$Elements: node tag");
        if (!nodes.count(node)) t.fail("$Elements: an element refers to node " + std::to_string(node) + ", which $Nodes does not define");
      }
    }
    seen += n;
  }
  if (seen != count)
    t.fail("$Elements: the blocks hold " + std::to_string(seen) + " elements, the header says " + std::to_string(count));
  t.expect("$EndElements");
}

void check_nodes_22(Tokens& t, std::unordered_set<long>& tags) {
  const long count = t.integer("$Nodes: number of nodes", 0, max_count);
  for (long i = 0; i < count; ++i) {
    const long tag = t.integer("$Nodes: node tag", 1);
    if (!tags.insert(tag).second) t.fail("$Nodes: node tag " + std::to_string(tag) + " is defined twice");
    for (int c = 0; c < 3; ++c) t.real("$Nodes: coordinate");
  }
  t.expect("$EndNodes");
}

void check_elements_22(Tokens& t, const std::unordered_set<long>& nodes) {
  const long count = t.integer("$Elements: number of elements", 0, max_count);
  for (long e = 0; e < count; ++e) {
    t.integer("$Elements: element tag", 1);
    const long type = t.integer("$Elements: element type");
    const int per = nodes_of_element_type(type);
    if (per < 0) t.fail("$Elements: element type " + std::to_string(type) + " is not one of a 2D mesh's");
    const long n_tags = t.integer("$Elements: number of tags", 0, 64);
    for (long k = 0; k < n_tags; ++k) t.integer("$Elements: tag");
    for (int k = 0; k < per; ++k) {
      const long node = t.integer("$Elements: node tag");
      if (!nodes.count(node)) t.fail("$Elements: an element refers to node " + std::to_string(node) + ", which $Nodes does not define");
    }
  }
  t.expect("$EndElements");
}

// $PhysicalNames (both formats): a count, then per name its dimension (0..3), a tag and the
// name in double quotes. gmsh 4.8 crashed on a name of dimension 4 (found by fuzzing).
void check_physical_names(Tokens& t) {
  const long count = t.integer("$PhysicalNames: number of names", 0, 10000);
  for (long k = 0; k < count; ++k) {
    t.integer("$PhysicalNames: dimension", 0, 3);
    t.integer("$PhysicalNames: tag", 1);
    std::string name = t.word();
    if (name.front() != '"') t.fail("$PhysicalNames: a name in double quotes expected, found '" + name + "'");
    while (name.size() < 2 || name.back() != '"') {
      if (name.size() > 256) t.fail("$PhysicalNames: a name longer than 256 characters, or without its closing quote");
      name += " " + t.word();
    }
  }
  t.expect("$EndPhysicalNames");
}

}  // namespace

void check_msh_file(const std::string& path) {
  Tokens t(path);
  t.expect("$MeshFormat");
  const std::string version = t.word();
  const long file_type = t.integer("$MeshFormat: file type", 0, 1);
  t.integer("$MeshFormat: data size");
  if (file_type != 0) t.fail("a binary mesh file; pilelab reads ASCII ones");
  if (version != "4.1" && version != "2.2") t.fail("mesh format version " + version + "; pilelab reads 4.1 and 2.2");
  t.expect("$EndMeshFormat");
  const bool v41 = version == "4.1";
  std::unordered_set<long> nodes;
  bool has_nodes = false, has_elements = false;
  while (!t.at_end()) {
    const std::string section = t.word();
    if (section.size() < 2 || section[0] != '$') t.fail("a section ($Name) expected, found '" + section + "'");
    const std::string name = section.substr(1);
    if (name == "Nodes") {
      if (has_nodes) t.fail("a second $Nodes section");
      v41 ? check_nodes_41(t, nodes) : check_nodes_22(t, nodes);
      has_nodes = true;
    } else if (name == "Elements") {
      if (!has_nodes) t.fail("$Elements before $Nodes");
      if (has_elements) t.fail("a second $Elements section");
      v41 ? check_elements_41(t, nodes) : check_elements_22(t, nodes);
      has_elements = true;
    } else if (name == "PhysicalNames") {
      check_physical_names(t);
    } else {
      t.skip_section(name);
    }
  }
  if (!has_nodes || !has_elements) throw InputError(path + ": no $Nodes or no $Elements section (expected a gmsh .msh file with a triangulation)");
}

}  // namespace pilelab::mesh
