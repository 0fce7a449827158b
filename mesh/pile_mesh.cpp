#include "mesh/pile_mesh.h"
#include "mesh/msh_check.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <gmsh.h>

#include "common/atomic_file.h"
#include "common/error.h"
#include "dem/dem_file.h"
#include "mesh/pile_outline.h"

namespace pilelab::mesh {

namespace {

constexpr double degree = M_PI / 180.0;

// gmsh keeps one global model; a session initialises it quietly and always finalises it, so
// that deal.II's own gmsh reader finds a clean state afterwards.
struct GmshSession {
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// Physical groups named as deal.II's reader expects ("BoundaryID:n"), tag n as well so the
// stream reader agrees.
void add_boundary_group(const std::vector<int>& curves, BoundaryId id) {
  if (curves.empty()) return;
  gmsh::model::addPhysicalGroup(1, curves, id);
  gmsh::model::setPhysicalName(1, id, "BoundaryID:" + std::to_string(id));
}

void add_material_group(const std::vector<int>& surfaces) {
  gmsh::model::addPhysicalGroup(2, surfaces, 100);
  gmsh::model::setPhysicalName(2, 100, "MaterialID:0");
}

// Lines through a chain of point tags; returns the line tags.
std::vector<int> chain(const std::vector<int>& points) {
  std::vector<int> lines;
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
    lines.push_back(gmsh::model::geo::addLine(points[i], points[i + 1]));
  return lines;
}

// The pile region bounded by the outline and the base y = 0. With embed_axis, the vertical
// through the apex splits it into two surfaces that share the axis, so element edges follow
// the axis; with rays (their feet on the base) the two FPA characteristics from the apex split
// it into four.
void build_pile(const Outline& outline, const MeshSpec& spec, const std::optional<RayFeet>& rays) {
  const auto& s = outline.surface;
  const int a = outline.apex_index;
  const double size = spec.element_size_m;
  const double axis_size = spec.axis_element_size_m > 0 ? spec.axis_element_size_m : size;
  std::vector<int> pt(s.size());
  for (std::size_t i = 0; i < s.size(); ++i)
    pt[i] = gmsh::model::geo::addPoint(s[i].x(), s[i].y(), 0.0, static_cast<int>(i) == a ? axis_size : size);
  const std::vector<int> left_points(pt.begin(), pt.begin() + a + 1);  // left foot .. apex
  const std::vector<int> right_points(pt.begin() + a, pt.end());       // apex .. right foot
  const std::vector<int> left_flank = chain(left_points);
  const std::vector<int> right_flank = chain(right_points);
  const bool split = spec.embed_axis && s[a].x() > s.front().x() && s[a].x() < s.back().x();
  std::vector<int> base, surfaces;
  if (split && rays) {
    // Four regions: the axis and the two characteristics, all meshed along.
    const int foot = gmsh::model::geo::addPoint(s[a].x(), 0.0, 0.0, axis_size);
    const int ray_left_foot = gmsh::model::geo::addPoint(rays->left_x, 0.0, 0.0, size);
    const int ray_right_foot = gmsh::model::geo::addPoint(rays->right_x, 0.0, 0.0, size);
    const int b0 = gmsh::model::geo::addLine(pt.front(), ray_left_foot);
    const int b1 = gmsh::model::geo::addLine(ray_left_foot, foot);
    const int b2 = gmsh::model::geo::addLine(foot, ray_right_foot);
    const int b3 = gmsh::model::geo::addLine(ray_right_foot, pt.back());
    const int axis = gmsh::model::geo::addLine(foot, pt[a]);
    const int ray_left = gmsh::model::geo::addLine(ray_left_foot, pt[a]);
    const int ray_right = gmsh::model::geo::addLine(ray_right_foot, pt[a]);
    base = {b0, b1, b2, b3};
    std::vector<int> outer_left = {b0, ray_left};
    for (auto it = left_flank.rbegin(); it != left_flank.rend(); ++it) outer_left.push_back(-*it);
    const std::vector<int> inner_left = {b1, axis, -ray_left};
    const std::vector<int> inner_right = {b2, ray_right, -axis};
    std::vector<int> outer_right = {b3};
    for (auto it = right_flank.rbegin(); it != right_flank.rend(); ++it) outer_right.push_back(-*it);
    outer_right.push_back(-ray_right);
    for (const auto& loop : {outer_left, inner_left, inner_right, outer_right})
      surfaces.push_back(gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(loop)}));
  } else if (split) {
    const int foot = gmsh::model::geo::addPoint(s[a].x(), 0.0, 0.0, axis_size);
    const int base_left = gmsh::model::geo::addLine(pt.front(), foot);
    const int base_right = gmsh::model::geo::addLine(foot, pt.back());
    const int axis = gmsh::model::geo::addLine(foot, pt[a]);
    base = {base_left, base_right};
    // Left region: foot of the left flank -> axis foot -> apex -> down the left flank.
    std::vector<int> left_loop = {base_left, axis};
    for (auto it = left_flank.rbegin(); it != left_flank.rend(); ++it) left_loop.push_back(-*it);
    // Right region: axis foot -> right foot -> up the right flank -> apex -> axis foot.
    std::vector<int> right_loop = {base_right};
    for (auto it = right_flank.rbegin(); it != right_flank.rend(); ++it) right_loop.push_back(-*it);
    right_loop.push_back(-axis);
    surfaces.push_back(gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(left_loop)}));
    surfaces.push_back(gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(right_loop)}));
  } else {
    const int base_line = gmsh::model::geo::addLine(pt.front(), pt.back());
    base = {base_line};
    std::vector<int> loop = {base_line};
    for (auto it = right_flank.rbegin(); it != right_flank.rend(); ++it) loop.push_back(-*it);
    for (auto it = left_flank.rbegin(); it != left_flank.rend(); ++it) loop.push_back(-*it);
    surfaces.push_back(gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(loop)}));
  }
  gmsh::model::geo::synchronize();
  add_boundary_group(base, BoundaryId::base);
  add_boundary_group(left_flank, BoundaryId::left_flank);
  add_boundary_group(right_flank, BoundaryId::right_flank);
  add_material_group(surfaces);
}

void build_block(const Block& b, double size) {
  const double w = b.width_m / 2;
  const std::vector<int> p = {gmsh::model::geo::addPoint(-w, 0, 0, size), gmsh::model::geo::addPoint(w, 0, 0, size),
                              gmsh::model::geo::addPoint(w, b.height_m, 0, size),
                              gmsh::model::geo::addPoint(-w, b.height_m, 0, size)};
  const std::vector<int> l = chain({p[0], p[1], p[2], p[3], p[0]});
  const int surface = gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(l)});
  gmsh::model::geo::synchronize();
  add_boundary_group({l[0]}, BoundaryId::base);
  add_boundary_group({l[1], l[3]}, BoundaryId::side_wall);
  add_boundary_group({l[2]}, BoundaryId::top);
  add_material_group({surface});
}

// Area enclosed by the outline and the base (shoelace over the closed polygon).
double outline_area(const Outline& o) {
  double twice = 0;
  const auto& s = o.surface;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const dem::Vec2& p = s[i];
    const dem::Vec2& q = s[(i + 1) % s.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(twice) / 2;
}

// Refuses meshes that would take more than a few minutes to make (a typo in a size).
void check_element_count(double area, const MeshSpec& spec) {
  const double estimate = estimated_triangle_count(area, spec);
  if (estimate > 4e6) {
    std::string sizes = "mesh.element_size_m = " + std::to_string(spec.element_size_m) + " m";
    if (spec.kind != MeshSpec::Kind::block && spec.axis_element_size_m > 0 &&
        spec.axis_element_size_m < spec.element_size_m)
      sizes += " and mesh.axis_element_size_m = " + std::to_string(spec.axis_element_size_m) + " m";
    char count[32];
    std::snprintf(count, sizeof count, "%.3g", estimate);  // may exceed any integer type
    throw InputError(sizes + " give about " + count + " triangles; expected at most 4e6 (raise the element sizes)");
  }
}

// Meshes the model gmsh holds and writes it as MSH 4.1 ASCII to tmp.
void generate_and_write(const std::string& tmp) {
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // Frontal-Delaunay: well-shaped triangles
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 0);
  gmsh::model::mesh::generate(2);
  // gmsh picks the format from the extension, so write X.msh and move it to the temporary name.
  const std::string with_extension = tmp + ".msh";
  gmsh::write(with_extension);
  // gmsh does not report a failed write (a full disk truncates the file silently): a complete
  // MSH file ends with its elements' section, so check that before the file goes anywhere.
  std::ifstream written(with_extension, std::ios::binary | std::ios::ate);
  const std::string ending = "$EndElements\n";
  std::string tail(ending.size(), '\0');
  const std::streamoff size = written ? static_cast<std::streamoff>(written.tellg()) : -1;
  if (size >= static_cast<std::streamoff>(ending.size())) {
    written.seekg(size - static_cast<std::streamoff>(ending.size()));
    written.read(tail.data(), static_cast<std::streamsize>(ending.size()));
  }
  if (!written || tail != ending) {
    std::remove(with_extension.c_str());
    throw InputError("cannot write " + with_extension + ": gmsh wrote " + (size < 0 ? std::string("nothing") : std::to_string(size) + " bytes") +
                     " and the file does not end with $EndElements (is the disk full?); the previous mesh is kept");
  }
  std::filesystem::rename(with_extension, tmp);
}

// Whether the closed segments pq and uv share a point (touching counts).
bool segments_meet(dem::Vec2 p, dem::Vec2 q, dem::Vec2 u, dem::Vec2 v) {
  const auto side = [](dem::Vec2 a, dem::Vec2 b, dem::Vec2 c) { return dem::cross(b - a, c - a); };
  const double d1 = side(u, v, p), d2 = side(u, v, q), d3 = side(p, q, u), d4 = side(p, q, v);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  const auto on = [](dem::Vec2 a, dem::Vec2 b, dem::Vec2 c, double d) {  // c on segment ab, given d = side(a, b, c)
    return d == 0 && std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) &&
           std::min(a.y(), b.y()) <= c.y() && c.y() <= std::max(a.y(), b.y());
  };
  return on(u, v, p, d1) || on(u, v, q, d2) || on(p, q, u, d3) || on(p, q, v, d4);
}

std::string point_text(dem::Vec2 p) {
  char text[64];
  std::snprintf(text, sizeof text, "(%.4g, %.4g) m", p.x(), p.y());
  return text;
}

}  // namespace

double estimated_triangle_count(double area, const MeshSpec& spec) {
  // An equilateral triangle of edge h has area 0.433 h^2.
  const double s = spec.element_size_m;
  const double a = spec.kind == MeshSpec::Kind::block || spec.axis_element_size_m <= 0
                       ? s
                       : std::min(spec.axis_element_size_m, s);
  if (!(a > 0)) return INFINITY;
  // gmsh grades the size from a (on the axis, or at the apex) up to s. Along an embedded axis
  // the count is about the uniform count plus a strip that grows as s / a: (2 s / a - 1) times
  // the uniform count. Around the apex alone the graded disc adds a logarithm: about
  // 1 + 1.5 ln(s / a) times. Both fitted to gmsh 4 (a 30/25 degree wedge, s / a from 1 to 40:
  // within 20 %).
  const double uniform = area / (0.433 * s * s);
  const bool axis_line = spec.kind != MeshSpec::Kind::block && spec.embed_axis;
  if (axis_line) return uniform * (2 * s / a - 1);
  return uniform * (1 + 1.5 * std::log(s / a));
}

MeshSpec read_mesh_scene(SceneReader& r, const std::string& scene_dir) {
  MeshSpec spec;
  const std::string kind = r.get_choice("mesh.kind", "wedge", {"wedge", "block", "dem_outline"});
  spec.kind = kind == "wedge" ? MeshSpec::Kind::wedge : kind == "block" ? MeshSpec::Kind::block
                                                                         : MeshSpec::Kind::dem_outline;
  spec.wedge.height_m = r.get_double("mesh.height_m", spec.wedge.height_m, Range::positive());
  spec.wedge.left_angle_deg = r.get_double("mesh.left_angle_deg", spec.wedge.left_angle_deg, {0, 90, true});
  spec.wedge.right_angle_deg = r.get_double("mesh.right_angle_deg", spec.wedge.right_angle_deg, {0, 90, true});
  spec.wedge.apex_x_m = r.get_double("mesh.apex_x_m", 0.0, Range{});
  spec.block.width_m = r.get_double("mesh.width_m", spec.block.width_m, Range::positive());
  spec.block.height_m = spec.wedge.height_m;
  if (spec.wedge.left_angle_deg >= 90 || spec.wedge.right_angle_deg >= 90)
    throw InputError(r.source() + ": mesh.left_angle_deg and mesh.right_angle_deg must lie in (0, 90) degrees");
  const std::string dem_file = r.get_string("mesh.dem_file", "");
  if (!dem_file.empty())
    spec.dem_file = std::filesystem::path(dem_file).is_absolute() ? dem_file
                                                                  : (std::filesystem::path(scene_dir) / dem_file).string();
  spec.dem_snapshot = r.get_string("mesh.dem_snapshot", spec.dem_snapshot);
  spec.outline_smoothing_grains =
      r.get_double("mesh.outline_smoothing_grains", spec.outline_smoothing_grains, Range::closed(0.0, 100.0));
  if (spec.outline_smoothing_grains > 0 && spec.outline_smoothing_grains < 0.5)
    throw InputError(r.source() + ": mesh.outline_smoothing_grains: " + std::to_string(spec.outline_smoothing_grains) +
                     " is below half a grain, where the average smooths nothing: expected 0 (no smoothing) or 0.5 .. 100");
  spec.element_size_m = r.get_double("mesh.element_size_m", spec.element_size_m, Range::positive());
  spec.axis_element_size_m = r.get_double("mesh.axis_element_size_m", 0.0, Range::at_least(0.0));
  spec.embed_axis = r.get_bool("mesh.embed_axis", spec.embed_axis);
  // On by default wherever the mesh allows (split at its axis): on a wedge the FPA is then
  // exact; on a DEM outline its largest kinks are edges.
  spec.embed_rays = r.get_bool("mesh.embed_fpa_rays", spec.kind != MeshSpec::Kind::block && spec.embed_axis);
  if (spec.embed_rays && (spec.kind == MeshSpec::Kind::block || !spec.embed_axis))
    throw InputError(r.source() +
                     ": mesh.embed_fpa_rays needs mesh.kind = \"wedge\" or \"dem_outline\" and mesh.embed_axis = true");
  // A DEM outline's rays: at the flank angles the scene gives, else at the angles the DEM
  // measured (the run hands them over, as it does to the FPA).
  if (spec.kind == MeshSpec::Kind::dem_outline && r.has("mesh.left_angle_deg"))
    spec.ray_left_angle_deg = spec.wedge.left_angle_deg;
  if (spec.kind == MeshSpec::Kind::dem_outline && r.has("mesh.right_angle_deg"))
    spec.ray_right_angle_deg = spec.wedge.right_angle_deg;
  return spec;
}

std::optional<RayFeet> fpa_ray_feet(const Outline& outline, double left_angle_deg, double right_angle_deg,
                                    std::string& why_not) {
  const auto& s = outline.surface;
  const int a = outline.apex_index, n = static_cast<int>(s.size());
  if (n < 3 || a <= 0 || a >= n - 1 || !(s[a].x() > s.front().x() && s[a].x() < s.back().x())) {
    why_not = "the outline has no apex between its feet";
    return std::nullopt;
  }
  const dem::Vec2 apex = s[a];
  RayFeet feet;
  for (const bool right : {false, true}) {
    const char* name = right ? "right" : "left";
    const double phi = right ? right_angle_deg : left_angle_deg;
    if (!(phi > 0 && phi < 90)) {
      why_not = std::string("no angle of repose for the ") + name + " ray";
      return std::nullopt;
    }
    char ray_name[64];
    std::snprintf(ray_name, sizeof ray_name, "the %s ray (phi = %.4g degrees)", name, phi);
    const double sign = right ? 1.0 : -1.0;
    const dem::Vec2 foot(apex.x() + sign * apex.y() * std::tan((45.0 - 0.5 * phi) * degree), 0.0);
    if (!(right ? foot.x() < s.back().x() : foot.x() > s.front().x())) {
      why_not = std::string(ray_name) + " meets the base at " + point_text(foot) + ", beyond the pile's foot at " +
                point_text(right ? s.back() : s.front());
      return std::nullopt;
    }
    // The edge at the apex on the ray's side must lie above the ray (sign * cross > 0 on the
    // flank's side), or the ray leaves the pile at once; the other side's edges lie across the
    // axis (the surface's x only grows) and meet this ray at most in the apex.
    const dem::Vec2 next = s[right ? a + 1 : a - 1];
    if (!(sign * dem::cross(foot - apex, next - apex) > 0)) {
      why_not = std::string(ray_name) + " leaves the pile at the apex: the surface next to it, towards " +
                point_text(next) + ", falls more steeply";
      return std::nullopt;
    }
    const int first = right ? a + 1 : 0, last = right ? n - 1 : a - 1;  // the edges (i, i + 1) beyond it
    for (int i = first; i < last; ++i)
      if (segments_meet(apex, foot, s[i], s[i + 1])) {
        why_not = std::string(ray_name) + " crosses the surface between " + point_text(s[i]) + " and " +
                  point_text(s[i + 1]);
        return std::nullopt;
      }
    (right ? feet.right_x : feet.left_x) = foot.x();
  }
  return feet;
}

Outline wedge_outline(const Wedge& w) {
  Outline o;
  o.surface = {{w.apex_x_m - w.height_m / std::tan(w.left_angle_deg * degree), 0.0},
               {w.apex_x_m, w.height_m},
               {w.apex_x_m + w.height_m / std::tan(w.right_angle_deg * degree), 0.0}};
  o.apex_index = 1;
  return o;
}

MeshOutcome write_mesh(const MeshSpec& spec, const std::string& msh_path) {
  Outline outline;
  switch (spec.kind) {
    case MeshSpec::Kind::wedge:
      outline = wedge_outline(spec.wedge);
      break;
    case MeshSpec::Kind::block: {
      check_element_count(spec.block.width_m * spec.block.height_m, spec);
      write_atomically(msh_path, [&](const std::string& tmp) {
        GmshSession session;
        gmsh::model::add("pile");
        build_block(spec.block, spec.element_size_m);
        generate_and_write(tmp);
      });
      return {};
    }
    case MeshSpec::Kind::dem_outline: {
      // Strips of one grain; the polyline keeps every feature above a quarter of that. The
      // outline depends on the grains alone, not on the element size, so that refining the mesh
      // refines one domain (a coarse mesh still follows the pile's shape: gmsh puts a node at
      // every vertex of it).
      double diameter = 0;  // the piles' mean grain diameter
      double tolerance = INFINITY;
      const auto outline_of = [&](const std::string& path) {
        const dem::DemFile file = dem::read_dem_file(path);
        const dem::Snapshot snapshot = file.snapshot(spec.dem_snapshot);
        const double d = mean_grain_diameter(file, snapshot);
        diameter = std::max(diameter, d);
        const double strip = d > 0 ? d : spec.element_size_m;
        tolerance = std::min(tolerance, strip / 4);
        return outline_of_pile(file, snapshot, strip, strip / 4);
      };
      if (!spec.dem_files.empty()) {
        // An ensemble: the members' mean surface.
        std::vector<Outline> members;
        for (const std::string& path : spec.dem_files) members.push_back(outline_of(path));
        outline = mean_outline(members, diameter > 0 ? diameter : spec.element_size_m);
      } else {
        if (spec.dem_file.empty()) throw InputError("mesh.kind = \"dem_outline\" needs mesh.dem_file (a dem.h5)");
        outline = outline_of(spec.dem_file);
      }
      // Smoothed over a few grains, then simplified: no surface point moves by more than the
      // tolerance from the smoothed surface, which keeps tiny edges out of the mesh.
      outline = smoothed_outline(outline, spec.outline_smoothing_grains * diameter);
      outline.surface = simplify_polyline(outline.surface, tolerance);
      outline.apex_index = 0;
      for (int i = 1; i + 1 < static_cast<int>(outline.surface.size()); ++i)
        if (outline.surface[i].y() > outline.surface[outline.apex_index].y()) outline.apex_index = i;
      break;
    }
  }
  return write_outline_mesh(outline, spec, msh_path);
}

MeshOutcome write_outline_mesh(const Outline& outline, const MeshSpec& spec, const std::string& msh_path) {
  check_element_count(outline_area(outline), spec);
  MeshOutcome outcome;
  std::optional<RayFeet> rays;
  if (spec.embed_rays && spec.embed_axis) {
    const bool wedge = spec.kind == MeshSpec::Kind::wedge;
    outcome.ray_left_angle_deg = wedge ? spec.wedge.left_angle_deg : spec.ray_left_angle_deg;
    outcome.ray_right_angle_deg = wedge ? spec.wedge.right_angle_deg : spec.ray_right_angle_deg;
    if (outcome.ray_left_angle_deg > 0 && outcome.ray_right_angle_deg > 0)
      rays = fpa_ray_feet(outline, outcome.ray_left_angle_deg, outcome.ray_right_angle_deg, outcome.rays_note);
    else
      outcome.rays_note = "no angles of repose known (give mesh.left_angle_deg and mesh.right_angle_deg, or run the dem stage)";
    outcome.rays_embedded = rays.has_value();
  }
  write_atomically(msh_path, [&](const std::string& tmp) {
    GmshSession session;
    gmsh::model::add("pile");
    build_pile(outline, spec, rays);
    generate_and_write(tmp);
  });
  return outcome;
}

double mesh_area(const TriangleMesh& m) {
  double a = 0;
  for (const auto& t : m.triangles) a += 0.5 * dem::cross(m.nodes[t[1]] - m.nodes[t[0]], m.nodes[t[2]] - m.nodes[t[0]]);
  return a;
}

TriangleMesh read_triangle_mesh(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe) throw InputError(path + ": cannot open the mesh file (expected a gmsh .msh file)");
  }
  check_msh_file(path);  // gmsh's reader crashes on some damaged files: refuse them first
  TriangleMesh mesh;
  GmshSession session;
  try {
    gmsh::open(path);
  } catch (...) {
    throw InputError(path + ": gmsh cannot read this file (expected a gmsh .msh file)");
  }
  std::vector<std::size_t> node_tags;
  std::vector<double> coords, parametric;
  gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
  std::map<std::size_t, int> index_of;
  for (std::size_t i = 0; i < node_tags.size(); ++i) {
    index_of[node_tags[i]] = static_cast<int>(i);
    if (!std::isfinite(coords[3 * i]) || !std::isfinite(coords[3 * i + 1]))
      throw InputError(path + ": node " + std::to_string(node_tags[i]) + " has a coordinate that is not a finite number");
    mesh.nodes.emplace_back(coords[3 * i], coords[3 * i + 1]);
  }
  // An element's node tag must name a node of the file.
  const auto node_index = [&](std::size_t tag, std::size_t element) {
    const auto it = index_of.find(tag);
    if (it == index_of.end())
      throw InputError(path + ": element " + std::to_string(element) + " refers to node " + std::to_string(tag) +
                       ", which the file does not define");
    return it->second;
  };
  std::vector<std::size_t> element_tags, element_nodes;
  gmsh::model::mesh::getElementsByType(2, element_tags, element_nodes);  // 3-node triangles
  if (element_tags.empty())
    throw InputError(path + ": the mesh holds no 3-node triangles (expected a 2D linear triangulation)");
  for (std::size_t e = 0; e < element_tags.size(); ++e) {
    std::array<int, 3> t{};
    for (int k = 0; k < 3; ++k) t[k] = node_index(element_nodes[3 * e + k], element_tags[e]);
    const double twice_area = dem::cross(mesh.nodes[t[1]] - mesh.nodes[t[0]], mesh.nodes[t[2]] - mesh.nodes[t[0]]);
    if (!(twice_area > 0))
      throw InputError(path + ": triangle " + std::to_string(element_tags[e]) +
                       " is inverted or degenerate (expected counter-clockwise triangles of positive area)");
    mesh.triangles.push_back(t);
  }
  // In a triangulation of counter-clockwise triangles each edge is traversed once in each
  // direction (inside) or once (on the boundary). A directed edge met twice means two triangles
  // lie on the same side of it: one triangle copied over another, or a mesh folded onto itself,
  // which would count the grains under it twice.
  std::map<std::pair<int, int>, std::size_t> edge_owner;
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e)
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> edge{mesh.triangles[e][k], mesh.triangles[e][(k + 1) % 3]};
      const auto [it, first] = edge_owner.emplace(edge, e);
      if (!first)
        throw InputError(path + ": triangles " + std::to_string(element_tags[it->second]) + " and " +
                         std::to_string(element_tags[e]) + " overlap (both lie on the same side of the edge from node " +
                         std::to_string(node_tags[edge.first]) + " to node " + std::to_string(node_tags[edge.second]) +
                         "; expected a triangulation without overlaps)");
    }
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 1);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    int id = tag;
    if (name.rfind("BoundaryID:", 0) == 0) {
      const std::string digits = name.substr(11);
      if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos)
        throw InputError(path + ": physical curve \"" + name + "\": expected BoundaryID:<number>");
      id = std::stoi(digits);
    }
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int entity : entities) {
      std::vector<std::size_t> tags, nodes;
      gmsh::model::mesh::getElementsByType(1, tags, nodes, entity);
      for (std::size_t e = 0; e < tags.size(); ++e) {
        mesh.boundary_edges.push_back({node_index(nodes[2 * e], tags[e]), node_index(nodes[2 * e + 1], tags[e])});
        mesh.boundary_edge_ids.push_back(id);
      }
    }
  }
  return mesh;
}

}  // namespace pilelab::mesh
