#include "dem/dem_file.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hdf5_file.h"

namespace pilelab::dem {

namespace {

using Dims = std::vector<std::uint64_t>;

const char* const note_2d =
    "2D: forces per unit depth are reported in N (E in N/m), masses from areal density";

std::string snapshot_group(const std::string& name) { return "/snapshots/" + name; }

std::string join(const std::vector<std::string>& names, char sep) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? std::string(1, sep) : "") + names[i];
  return out;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find(sep, start);
    out.push_back(text.substr(start, end - start));
    if (end == std::string::npos) return out;
    start = end + 1;
  }
}

std::string dims_text(const Dims& d) {
  std::string s = "(";
  for (std::size_t i = 0; i < d.size(); ++i) s += (i ? ", " : "") + std::to_string(d[i]);
  return s + (d.size() == 1 ? ",)" : ")");
}

// ---------------------------------------------------------------------------- writing

// Names become HDF5 group names and entries of the comma-separated "order" attribute.
void check_snapshot_names(const std::vector<Snapshot>& snapshots) {
  std::set<std::string> seen;
  for (const Snapshot& s : snapshots) {
    if (s.name.empty() || s.name.find_first_of(",/") != std::string::npos || s.name == "." || s.name == "..")
      throw std::invalid_argument("dem.h5: snapshot name '" + s.name + "' is empty or contains ',' or '/'");
    if (!seen.insert(s.name).second) throw std::invalid_argument("dem.h5: snapshot name '" + s.name + "' repeated");
  }
}

void write_run_info(H5File& f, const nlohmann::json& run_info) {
  if (run_info.is_null()) return;
  if (!run_info.is_object()) throw std::invalid_argument("dem.h5: run_info must be a JSON object");
  for (const auto& [key, value] : run_info.items()) {
    if (value.is_string()) {
      f.set_attribute("/run", key, value.get<std::string>());
    } else if (value.is_boolean()) {
      f.set_attribute("/run", key, std::int64_t(value.get<bool>() ? 1 : 0));
    } else if (value.is_number_unsigned() && value.get<std::uint64_t>() > std::uint64_t(INT64_MAX)) {
      f.set_attribute("/run", key, value.get<double>());  // too large for int64: keep the magnitude
    } else if (value.is_number_integer()) {
      f.set_attribute("/run", key, value.get<std::int64_t>());
    } else if (value.is_number()) {
      f.set_attribute("/run", key, value.get<double>());
    } else {
      // Not flat (array, object, null): keep it readable rather than drop it.
      f.set_attribute("/run", key, value.dump());
    }
  }
}

void write_bodies(H5File& f, const World& world) {
  const int n = world.body_count();
  std::vector<std::int64_t> kind, is_wall, offset{0};
  std::vector<double> mass, inertia, area, radius, bounding, vertices;
  for (int i = 0; i < n; ++i) {
    const Shape& s = world.shape(i);
    kind.push_back(static_cast<std::int64_t>(s.kind));
    is_wall.push_back(world.is_wall(i) ? 1 : 0);
    // World gives walls infinite mass; 0 is the file's marker for "immobile" (no inf in files).
    mass.push_back(world.is_wall(i) ? 0.0 : world.mass(i));
    inertia.push_back(world.is_wall(i) ? 0.0 : world.inertia(i));
    area.push_back(s.area);
    radius.push_back(s.kind == ShapeKind::disc ? s.radius : 0.0);
    bounding.push_back(s.bounding_radius);
    for (const Vec2& v : s.vertices) vertices.insert(vertices.end(), {v.x(), v.y()});
    offset.push_back(offset.back() + static_cast<std::int64_t>(s.vertices.size()));
  }
  f.write("/bodies/kind", kind);
  f.write("/bodies/is_wall", is_wall);
  f.write("/bodies/mass", mass, {}, "kg");
  f.write("/bodies/moment_of_inertia", inertia, {}, "kg m^2");
  f.write("/bodies/area", area, {}, "m^2");
  f.write("/bodies/radius", radius, {}, "m");
  f.write("/bodies/bounding_radius", bounding, {}, "m");
  f.write("/bodies/vertex_offset", offset);
  f.write("/bodies/vertices", vertices, {vertices.size() / 2, 2}, "m");
}

void write_snapshot(H5File& f, const Snapshot& s, const WallPlacement& walls) {
  const std::string g = snapshot_group(s.name);
  const std::uint64_t n = s.body.size(), c = s.normal_force.size(), w = walls.angle.size();
  f.set_attribute(g, "time_s", s.time);
  f.set_attribute(g, "gravity_m_per_s2", s.gravity);
  f.set_attribute(g, "grain_count", static_cast<std::int64_t>(n));
  f.set_attribute(g, "contact_count", static_cast<std::int64_t>(c));
  f.write(g + "/body", s.body);
  f.write(g + "/position", s.position, {n, 2}, "m");
  f.write(g + "/angle", s.angle, {n}, "rad");
  f.write(g + "/velocity", s.velocity, {n, 2}, "m/s");
  f.write(g + "/angular_velocity", s.angular_velocity, {n}, "rad/s");
  f.write(g + "/contact_force", s.contact_force, {n, 2}, "N");
  f.write(g + "/contact_count", s.contact_count, {n});
  f.write(g + "/contacts/pair", s.pair, {c, 2});
  f.write(g + "/contacts/point", s.point, {c, 2}, "m");
  f.write(g + "/contacts/normal", s.normal, {c, 2}, "1");
  f.write(g + "/contacts/normal_force", s.normal_force, {c}, "N");
  f.write(g + "/contacts/tangential_force", s.tangential_force, {c}, "N");
  f.write(g + "/contacts/force", s.force, {c, 2}, "N");
  f.write(g + "/contacts/overlap_area", s.overlap_area, {c}, "m^2");
  f.write(g + "/contacts/chord", s.chord, {c}, "m");
  f.write(g + "/wall_position", walls.position, {w, 2}, "m");
  f.write(g + "/wall_angle", walls.angle, {w}, "rad");
  f.write(g + "/wall_velocity", walls.velocity, {w, 2}, "m/s");
}

// ---------------------------------------------------------------------------- reading

[[noreturn]] void fail(const std::string& path, const std::string& object, const std::string& what) {
  throw InputError(path + ": " + object + ": " + what);
}

// A number stored as an attribute (a snapshot's time and gravity, the run's figures) is as
// physical as a dataset's: a NaN or infinity is refused here, not carried into fields.h5.
double finite_attribute(const H5File& f, const std::string& object, const std::string& name) {
  const double value = f.attribute_double(object, name);
  if (!std::isfinite(value))
    fail(f.path(), object, "attribute " + name + " is " + (std::isnan(value) ? "NaN" : "infinite") + "; expected a finite number");
  return value;
}

void expect_dims(const H5File& f, const std::string& name, const Dims& got, const Dims& want) {
  if (got != want) fail(f.path(), name, "shape " + dims_text(got) + ", expected " + dims_text(want));
}

// Every number of a dem.h5 is a physical value: a NaN or an infinity is damage, refused with
// its row (and column) rather than carried into the fields.
std::vector<double> read_doubles(const H5File& f, const std::string& name, const Dims& want) {
  Dims got;
  std::vector<double> v = f.read_doubles(name, &got);
  expect_dims(f, name, got, want);
  const std::size_t columns = want.size() > 1 ? static_cast<std::size_t>(want[1]) : 1;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      fail(f.path(), name,
           "row " + std::to_string(i / columns) + (columns > 1 ? ", column " + std::to_string(i % columns) : std::string()) +
               " is " + (std::isnan(v[i]) ? "NaN" : "infinite") + "; expected finite numbers");
  return v;
}

// A grain's mass, moment of inertia and area are positive (walls carry zeros).
void require_positive_for_grains(const H5File& f, const std::string& name, const std::vector<double>& v,
                                 const std::vector<std::int64_t>& is_wall) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!is_wall[i] && !(v[i] > 0))
      fail(f.path(), name, "row " + std::to_string(i) + " (a grain) is " + std::to_string(v[i]) + "; expected a positive value");
}

std::vector<std::int64_t> read_ints(const H5File& f, const std::string& name, const Dims& want) {
  Dims got;
  std::vector<std::int64_t> v = f.read_ints(name, &got);
  expect_dims(f, name, got, want);
  return v;
}

// The length of a dataset whose first dimension defines a count, with its rank checked.
std::vector<std::int64_t> read_ints_defining_count(const H5File& f, const std::string& name, std::size_t rank,
                                                   std::uint64_t& count) {
  Dims got;
  std::vector<std::int64_t> v = f.read_ints(name, &got);
  const bool ok = got.size() == rank && (rank == 1 || got[1] == 2);
  if (!ok) fail(f.path(), name, "shape " + dims_text(got) + ", expected " + (rank == 1 ? "(n,)" : "(n, 2)"));
  count = got[0];
  return v;
}

void check_header(const H5File& f) {
  const std::string format = f.attribute_string("/", "format");
  if (format != dem_file_format)
    fail(f.path(), "/", "attribute format is '" + format + "', expected '" + dem_file_format + "'");
  const std::int64_t version = f.attribute_int("/", "format_version");
  if (version != dem_file_format_version)
    fail(f.path(), "/", "format_version is " + std::to_string(version) + "; this build reads version " +
                            std::to_string(dem_file_format_version));
}

// The derived shape quantities are not stored: recompute them as make_polygon/make_disc do.
Shape shape_from_record(ShapeKind kind, std::vector<Vec2> vertices, double radius, double area, double bounding) {
  Shape s;
  s.kind = kind;
  s.area = area;
  s.bounding_radius = bounding;
  if (kind == ShapeKind::disc) {
    s.radius = radius;
    s.polar_moment = 0.5 * M_PI * radius * radius * radius * radius;
    s.inner_radius = radius;
    s.longest_edge = 2.0 * radius;
    return s;
  }
  s.polar_moment = polygon_moments(vertices).polar_moment_about_centroid;
  s.inner_radius = INFINITY;
  const std::size_t m = vertices.size();
  for (std::size_t k = 0; k < m; ++k) {
    const Vec2& a = vertices[k];
    const Vec2& b = vertices[(k + 1) % m];
    const double edge = (b - a).norm();
    s.longest_edge = std::max(s.longest_edge, edge);
    s.inner_radius = std::min(s.inner_radius, cross(b - a, -a) / edge);
  }
  s.vertices = std::move(vertices);
  return s;
}

void read_bodies(const H5File& f, DemFile& out) {
  std::uint64_t n = 0;
  const std::vector<std::int64_t> kind = read_ints_defining_count(f, "/bodies/kind", 1, n);
  out.is_wall = read_ints(f, "/bodies/is_wall", {n});
  out.mass = read_doubles(f, "/bodies/mass", {n});
  out.moment_of_inertia = read_doubles(f, "/bodies/moment_of_inertia", {n});
  const std::vector<double> area = read_doubles(f, "/bodies/area", {n});
  const std::vector<double> radius = read_doubles(f, "/bodies/radius", {n});
  const std::vector<double> bounding = read_doubles(f, "/bodies/bounding_radius", {n});
  require_positive_for_grains(f, "/bodies/mass", out.mass, out.is_wall);
  require_positive_for_grains(f, "/bodies/moment_of_inertia", out.moment_of_inertia, out.is_wall);
  require_positive_for_grains(f, "/bodies/area", area, out.is_wall);
  for (std::uint64_t i = 0; i < n; ++i)  // a disc's radius; polygons carry 0
    if (kind[i] == 1 && !out.is_wall[i] && !(radius[i] > 0))
      fail(f.path(), "/bodies/radius", "row " + std::to_string(i) + " (a disc) is " + std::to_string(radius[i]) +
                                           "; expected a positive radius");
  const std::vector<std::int64_t> offset = read_ints(f, "/bodies/vertex_offset", {n + 1});
  if (offset[0] != 0) fail(f.path(), "/bodies/vertex_offset", "must start at 0");
  for (std::uint64_t i = 0; i < n; ++i)
    if (offset[i + 1] < offset[i]) fail(f.path(), "/bodies/vertex_offset", "must not decrease");
  const std::vector<double> xy = read_doubles(f, "/bodies/vertices", {std::uint64_t(offset[n]), 2});

  bool walls_done = false;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::string body = " (body " + std::to_string(i) + ")";
    if (kind[i] != 0 && kind[i] != 1) fail(f.path(), "/bodies/kind", "values must be 0 or 1" + body);
    if (out.is_wall[i] != 0 && out.is_wall[i] != 1) fail(f.path(), "/bodies/is_wall", "values must be 0 or 1" + body);
    if (out.is_wall[i] && walls_done) fail(f.path(), "/bodies/is_wall", "walls must come before grains" + body);
    walls_done = walls_done || !out.is_wall[i];
    const ShapeKind k = static_cast<ShapeKind>(kind[i]);
    const std::int64_t corners = offset[i + 1] - offset[i];
    if (k == ShapeKind::polygon && corners < 3)
      fail(f.path(), "/bodies/vertex_offset", "a polygon needs at least 3 vertices" + body);
    if (k == ShapeKind::disc && corners != 0) fail(f.path(), "/bodies/vertex_offset", "a disc has no vertices" + body);
    std::vector<Vec2> v;
    for (std::int64_t j = offset[i]; j < offset[i + 1]; ++j) v.emplace_back(xy[2 * j], xy[2 * j + 1]);
    out.shapes.push_back(shape_from_record(k, std::move(v), radius[i], area[i], bounding[i]));
  }
}

}  // namespace

WallPlacement take_wall_placement(const World& world) {
  WallPlacement w;
  for (int i = 0; i < world.wall_count(); ++i) {
    const Vec2 p = world.position(i), v = world.velocity(i);
    w.position.insert(w.position.end(), {p.x(), p.y()});
    w.angle.push_back(world.angle(i));
    w.velocity.insert(w.velocity.end(), {v.x(), v.y()});
  }
  return w;
}

void write_dem_file(const std::string& path, const std::string& scene_text, const World& world,
                    const std::vector<Snapshot>& snapshots, const std::vector<WallPlacement>& walls,
                    const nlohmann::json& run_info) {
  check_snapshot_names(snapshots);
  if (walls.size() != snapshots.size())
    throw std::invalid_argument("dem.h5: one wall placement per snapshot is needed");
  const std::size_t w = static_cast<std::size_t>(world.wall_count());
  for (const WallPlacement& p : walls)
    if (p.angle.size() != w || p.position.size() != 2 * w || p.velocity.size() != 2 * w)
      throw std::invalid_argument("dem.h5: a wall placement does not match the world's wall count");

  write_atomically(path, [&](const std::string& tmp) {
    H5File f = H5File::create(tmp);
    f.set_attribute("/", "format", std::string(dem_file_format));
    f.set_attribute("/", "format_version", dem_file_format_version);
    f.set_attribute("/", "length_unit", std::string("m"));
    f.set_attribute("/", "time_unit", std::string("s"));
    f.set_attribute("/", "mass_unit", std::string("kg"));
    f.set_attribute("/", "force_unit", std::string("N"));
    f.set_attribute("/", "note", std::string(note_2d));
    f.write_string("/scene", scene_text);
    write_run_info(f, run_info);
    write_bodies(f, world);
    std::vector<std::string> names;
    for (std::size_t k = 0; k < snapshots.size(); ++k) {
      write_snapshot(f, snapshots[k], walls[k]);
      names.push_back(snapshots[k].name);
    }
    // HDF5 lists group members alphabetically; the order attribute keeps the run's order.
    f.set_attribute("/snapshots", "order", join(names, ','));
    f.close();  // before the rename: a failed flush must not replace a good file
  });
}

void write_dem_file(const std::string& path, const std::string& scene_text, const World& world,
                    const std::vector<Snapshot>& snapshots, const nlohmann::json& run_info) {
  const WallPlacement now = take_wall_placement(world);
  std::vector<WallPlacement> walls;
  for (const Snapshot& s : snapshots) {
    WallPlacement p = now;
    const double back = world.time() - s.time;
    // Fixed walls are skipped so that their position is kept bit for bit.
    for (std::size_t k = 0; k < p.position.size(); ++k)
      if (p.velocity[k] != 0.0) p.position[k] -= p.velocity[k] * back;
    walls.push_back(std::move(p));
  }
  write_dem_file(path, scene_text, world, snapshots, walls, run_info);
}

DemFile read_dem_file(const std::string& path) {
  const H5File f = H5File::open_read(path);
  check_header(f);
  DemFile out;
  out.path = path;
  out.scene_text = f.read_string("/scene");
  read_bodies(f, out);
  out.snapshot_names = split(f.attribute_string("/snapshots", "order"), ',');
  for (const std::string& name : out.snapshot_names)
    if (!f.exists(snapshot_group(name)))
      fail(path, snapshot_group(name), "missing group (listed in the order attribute of /snapshots)");
  return out;
}

int DemFile::wall_count() const {
  return static_cast<int>(std::count(is_wall.begin(), is_wall.end(), std::int64_t(1)));
}

bool DemFile::has_snapshot(const std::string& name) const {
  return std::find(snapshot_names.begin(), snapshot_names.end(), name) != snapshot_names.end();
}

Snapshot DemFile::snapshot(const std::string& name) const {
  const std::string g = snapshot_group(name);
  if (!has_snapshot(name)) fail(path, g, "no such snapshot (the file has: " + join(snapshot_names, ',') + ")");
  const H5File f = H5File::open_read(path);
  Snapshot s;
  s.name = name;
  s.time = finite_attribute(f, g, "time_s");
  s.gravity = finite_attribute(f, g, "gravity_m_per_s2");

  std::uint64_t n = 0, c = 0;
  s.body = read_ints_defining_count(f, g + "/body", 1, n);
  if (f.attribute_int(g, "grain_count") != static_cast<std::int64_t>(n))
    fail(path, g, "attribute grain_count does not match the length of " + g + "/body");
  const std::int64_t first_grain = wall_count();
  std::vector<bool> seen(static_cast<std::size_t>(std::max<std::int64_t>(body_count(), 0)), false);
  for (std::size_t row = 0; row < s.body.size(); ++row) {
    const std::int64_t b = s.body[row];
    if (b < first_grain || b >= body_count())
      fail(path, g + "/body", "grain index " + std::to_string(b) + " is not a grain of /bodies");
    if (seen[static_cast<std::size_t>(b)])
      fail(path, g + "/body", "row " + std::to_string(row) + " names grain " + std::to_string(b) + " a second time");
    seen[static_cast<std::size_t>(b)] = true;
  }
  s.position = read_doubles(f, g + "/position", {n, 2});
  s.angle = read_doubles(f, g + "/angle", {n});
  s.velocity = read_doubles(f, g + "/velocity", {n, 2});
  s.angular_velocity = read_doubles(f, g + "/angular_velocity", {n});
  s.contact_force = read_doubles(f, g + "/contact_force", {n, 2});
  s.contact_count = read_ints(f, g + "/contact_count", {n});

  s.pair = read_ints_defining_count(f, g + "/contacts/pair", 2, c);
  if (f.attribute_int(g, "contact_count") != static_cast<std::int64_t>(c))
    fail(path, g, "attribute contact_count does not match the length of " + g + "/contacts/pair");
  for (std::uint64_t k = 0; k < c; ++k)
    if (s.pair[2 * k] < 0 || s.pair[2 * k] >= s.pair[2 * k + 1] || s.pair[2 * k + 1] >= body_count())
      fail(path, g + "/contacts/pair", "row " + std::to_string(k) + " is not a pair of body indices a < b");
  s.point = read_doubles(f, g + "/contacts/point", {c, 2});
  s.normal = read_doubles(f, g + "/contacts/normal", {c, 2});
  s.normal_force = read_doubles(f, g + "/contacts/normal_force", {c});
  s.tangential_force = read_doubles(f, g + "/contacts/tangential_force", {c});
  s.force = read_doubles(f, g + "/contacts/force", {c, 2});
  s.overlap_area = read_doubles(f, g + "/contacts/overlap_area", {c});
  s.chord = read_doubles(f, g + "/contacts/chord", {c});
  return s;
}

WallPlacement DemFile::walls(const std::string& name) const {
  const std::string g = snapshot_group(name);
  if (!has_snapshot(name)) fail(path, g, "no such snapshot (the file has: " + join(snapshot_names, ',') + ")");
  const H5File f = H5File::open_read(path);
  const std::uint64_t w = static_cast<std::uint64_t>(wall_count());
  WallPlacement p;
  p.position = read_doubles(f, g + "/wall_position", {w, 2});
  p.angle = read_doubles(f, g + "/wall_angle", {w});
  p.velocity = read_doubles(f, g + "/wall_velocity", {w, 2});
  return p;
}

double DemFile::run_number(const std::string& key) const {
  return finite_attribute(H5File::open_read(path), "/run", key);
}

std::int64_t DemFile::run_int(const std::string& key) const {
  return H5File::open_read(path).attribute_int("/run", key);
}

std::string DemFile::run_string(const std::string& key) const {
  return H5File::open_read(path).attribute_string("/run", key);
}

}  // namespace pilelab::dem
