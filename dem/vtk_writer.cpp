#include "dem/vtk_writer.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <locale>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/portable_math.h"

namespace pilelab::dem {

namespace {

constexpr int vtk_line = 3;
constexpr int vtk_polygon = 7;

// A cell-data array: integers or doubles, with its VTK type name.
struct CellArray {
  std::string name;
  std::string type;  // "Int32", "Int64" or "Float64"
  int components = 1;
  std::vector<std::int64_t> ints;
  std::vector<double> reals;
};

// What one VTU file holds: points (3 coordinates each), cells as VTK connectivity/offsets/types,
// and the cell-data arrays.
struct Grid {
  std::vector<double> points;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<int> types;
  std::vector<CellArray> cell_data;

  void add_point(const Vec2& p) { points.insert(points.end(), {p.x(), p.y(), 0.0}); }
  void close_cell(int type) {
    for (std::int64_t k = offsets.empty() ? 0 : offsets.back(); k < point_count(); ++k) connectivity.push_back(k);
    offsets.push_back(point_count());
    types.push_back(type);
  }
  std::int64_t point_count() const { return static_cast<std::int64_t>(points.size() / 3); }
  CellArray& array(const std::string& name, const std::string& type, int components = 1) {
    cell_data.push_back({name, type, components, {}, {}});
    return cell_data.back();
  }
};

std::ostringstream make_stream(int precision) {
  std::ostringstream s;
  s.imbue(std::locale::classic());  // a '.' decimal point whatever the user's locale
  s << std::setprecision(precision);
  return s;
}

// Values one tuple per line (scalars a dozen per line). The element always has text (at least
// a newline): some readers fail on an empty element.
template <class T>
void write_values(std::ostream& out, const std::vector<T>& values, int components) {
  const std::size_t per_line = components == 1 ? 12 : static_cast<std::size_t>(components);
  out << "\n";
  for (std::size_t i = 0; i < values.size(); ++i) out << values[i] << ((i + 1) % per_line == 0 ? "\n" : " ");
  if (values.size() % per_line != 0) out << "\n";
}

void write_data_array(std::ostream& out, const std::string& name, const std::string& type, int components,
                      const std::vector<std::int64_t>* ints, const std::vector<double>* reals) {
  // Scalars without NumberOfComponents, as VTK itself writes them (meshio reads a stated 1
  // as an (n, 1) array).
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
  if (components != 1) out << " NumberOfComponents=\"" << components << "\"";
  out << " format=\"ascii\">";
  if (ints) write_values(out, *ints, components);
  if (reals) write_values(out, *reals, components);
  out << "        </DataArray>\n";
}

// Doubles with 10 significant digits: plenty for pictures, and the files stay a third smaller
// than with round-trip precision. The exact values are in dem.h5.
std::string vtu_text(const Grid& g, double time) {
  std::ostringstream out = make_stream(10);
  const std::vector<std::int64_t> types(g.types.begin(), g.types.end());
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- pilelab DEM output. Units: m, s, rad; forces in N per unit depth (2D); see docs/FORMAT.md -->\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <FieldData>\n"
      // TimeValue is the name ParaView reads as the time of each file of a series; TIME is kept
      // for readers of earlier files.
      << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">"
      << std::setprecision(std::numeric_limits<double>::max_digits10) << time << "</DataArray>\n"
      << "      <DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">" << time
      << std::setprecision(10) << "</DataArray>\n"
      << "    </FieldData>\n"
      << "    <Piece NumberOfPoints=\"" << g.point_count() << "\" NumberOfCells=\"" << g.types.size() << "\">\n"
      << "      <Points>\n";
  write_data_array(out, "Points", "Float64", 3, nullptr, &g.points);
  out << "      </Points>\n      <Cells>\n";
  write_data_array(out, "connectivity", "Int64", 1, &g.connectivity, nullptr);
  write_data_array(out, "offsets", "Int64", 1, &g.offsets, nullptr);
  write_data_array(out, "types", "UInt8", 1, &types, nullptr);
  out << "      </Cells>\n      <CellData>\n";
  for (const CellArray& a : g.cell_data)
    write_data_array(out, a.name, a.type, a.components, a.type == "Float64" ? nullptr : &a.ints,
                     a.type == "Float64" ? &a.reals : nullptr);
  out << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out.str();
}

// The outline in world coordinates from the body's position and angle (not World::corners(),
// which are placed at the predicted position of the last step), so that the picture matches
// the velocities and the snapshot of the same instant.
void add_outline(Grid& g, const World& world, int body) {
  const Shape& s = world.shape(body);
  const Vec2 p = world.position(body);
  const double th = world.angle(body);
  if (s.kind == ShapeKind::disc) {
    for (int k = 0; k < disc_outline_corners; ++k) {
      const double phi = th + 2.0 * M_PI * k / disc_outline_corners;
      g.add_point(p + s.radius * Vec2(portable_cos(phi), portable_sin(phi)));
    }
  } else {
    double sn, c;
    rotation_sincos(th, sn, c);
    for (const Vec2& v : s.vertices) g.add_point(p + rotate(v, c, sn));
  }
  g.close_cell(vtk_polygon);
}

// Each body's stress moment sum over its contacts of (x_c - x_b) (x) f_c, f_c the force on the
// body (paper eq. 10 for one grain, before the division by its area); xx, xy, yx, yy.
std::vector<std::array<double, 4>> stress_moments(const World& world) {
  std::vector<std::array<double, 4>> m(world.body_count(), {0.0, 0.0, 0.0, 0.0});
  for (const Contact& c : world.contacts()) {
    const Vec2 f = c.force_on_b();
    for (const auto& [body, sign] : {std::pair<int, double>{c.b, 1.0}, std::pair<int, double>{c.a, -1.0}}) {
      const Vec2 arm = c.point - world.position(body);
      m[body][0] += sign * arm.x() * f.x();
      m[body][1] += sign * arm.x() * f.y();
      m[body][2] += sign * arm.y() * f.x();
      m[body][3] += sign * arm.y() * f.y();
    }
  }
  return m;
}

std::vector<std::int64_t> contacts_per_body(const World& world) {
  std::vector<std::int64_t> count(world.body_count(), 0);
  for (const Contact& c : world.contacts()) {
    ++count[c.a];
    ++count[c.b];
  }
  return count;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

// One VTK_POLYGON cell per body of `bodies`, with the cell data write_grains_vtu lists.
void write_bodies_vtu(const std::string& path, const World& world, const std::vector<int>& bodies) {
  Grid g;
  const std::vector<std::int64_t> count = contacts_per_body(world);
  const std::vector<std::array<double, 4>> moment = stress_moments(world);
  std::vector<std::int64_t> body, is_wall, contact_count;
  std::vector<double> velocity, angular_velocity, contact_force, speed, angle, area, radius, stress, pressure;
  for (int b : bodies) {
    add_outline(g, world, b);
    const Vec2 v = world.velocity(b), f = world.contact_force(b);
    body.push_back(b);
    is_wall.push_back(world.is_wall(b) ? 1 : 0);
    velocity.insert(velocity.end(), {v.x(), v.y(), 0.0});
    angular_velocity.push_back(world.angular_velocity(b));
    contact_force.insert(contact_force.end(), {f.x(), f.y(), 0.0});
    contact_count.push_back(count[b]);
    speed.push_back(v.norm());
    angle.push_back(world.angle(b));
    const double a = world.shape(b).area;
    area.push_back(a);
    radius.push_back(std::sqrt(a / M_PI));
    // The grain's mean stress (tension positive, symmetric part) and pressure, N/m; walls 0.
    const auto& m = moment[b];
    const double sxx = world.is_wall(b) ? 0.0 : m[0] / a, syy = world.is_wall(b) ? 0.0 : m[3] / a;
    const double sxy = world.is_wall(b) ? 0.0 : 0.5 * (m[1] + m[2]) / a;
    stress.insert(stress.end(), {sxx, sxy, 0.0, sxy, syy, 0.0, 0.0, 0.0, 0.0});
    pressure.push_back(-0.5 * (sxx + syy));
  }
  g.array("body", "Int64").ints = std::move(body);
  g.array("is_wall", "Int32").ints = std::move(is_wall);
  g.array("velocity", "Float64", 3).reals = std::move(velocity);
  g.array("angular_velocity", "Float64").reals = std::move(angular_velocity);
  g.array("contact_force", "Float64", 3).reals = std::move(contact_force);
  g.array("contact_count", "Int32").ints = std::move(contact_count);
  g.array("speed", "Float64").reals = std::move(speed);
  g.array("angle", "Float64").reals = std::move(angle);
  g.array("area", "Float64").reals = std::move(area);
  g.array("equivalent_radius", "Float64").reals = std::move(radius);
  g.array("stress", "Float64", 9).reals = std::move(stress);
  g.array("pressure", "Float64").reals = std::move(pressure);
  write_text_atomically(path, vtu_text(g, world.time()));
}
}  // namespace

void write_grains_vtu(const std::string& path, const World& world) {
  write_bodies_vtu(path, world, std::vector<int>(world.active_grains().begin(), world.active_grains().end()));
}

void write_walls_vtu(const std::string& path, const World& world) {
  std::vector<int> walls(static_cast<std::size_t>(world.wall_count()));
  for (int w = 0; w < world.wall_count(); ++w) walls[static_cast<std::size_t>(w)] = w;
  write_bodies_vtu(path, world, walls);
}

void write_contacts_vtu(const std::string& path, const World& world) {
  Grid g;
  std::vector<std::int64_t> body_a, body_b;
  std::vector<double> normal_force, tangential_force, force, overlap_area, chord;
  for (const Contact& c : world.contacts()) {
    // A wall's centroid can be far away (a long floor): start its line at the contact point.
    g.add_point(world.is_wall(c.a) ? c.point : world.position(c.a));
    g.add_point(world.position(c.b));
    g.close_cell(vtk_line);
    body_a.push_back(c.a);
    body_b.push_back(c.b);
    normal_force.push_back(c.normal_force);
    tangential_force.push_back(c.tangential_force);
    const Vec2 f = c.force_on_b();
    force.insert(force.end(), {f.x(), f.y(), 0.0});
    overlap_area.push_back(c.area);
    chord.push_back(c.chord);
  }
  g.array("body_a", "Int64").ints = std::move(body_a);
  g.array("body_b", "Int64").ints = std::move(body_b);
  g.array("normal_force", "Float64").reals = std::move(normal_force);
  g.array("tangential_force", "Float64").reals = std::move(tangential_force);
  g.array("force", "Float64", 3).reals = std::move(force);
  g.array("overlap_area", "Float64").reals = std::move(overlap_area);
  g.array("chord", "Float64").reals = std::move(chord);
  write_text_atomically(path, vtu_text(g, world.time()));
}

PvdSeries::PvdSeries(std::string path) : path_(std::move(path)) {}

void PvdSeries::add(double time, const std::string& vtu_file_relative, int part, const std::string& name) {
  entries_.push_back({time, vtu_file_relative, part, name});
}

namespace {
const char* const pvd_head =
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
const char* const pvd_tail = "  </Collection>\n</VTKFile>\n";
}  // namespace

std::string PvdSeries::entry_text(const Entry& e) {
  // Round-trip precision: ParaView matches the times of different parts exactly.
  std::ostringstream out = make_stream(std::numeric_limits<double>::max_digits10);
  out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\""
      << (e.name.empty() ? std::string() : " name=\"" + xml_escape(e.name) + "\"") << " file=\"" << xml_escape(e.file)
      << "\"/>\n";
  return out.str();
}

void PvdSeries::write_whole() {
  std::string text = pvd_head;
  for (const Entry& e : entries_) text += entry_text(e);
  text += pvd_tail;
  write_text_atomically(path_, text);
  entries_written_ = entries_.size();
  bytes_written_ = text.size();
}

void PvdSeries::write() {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path_, ec);
  if (bytes_written_ == 0 || ec || size != bytes_written_) return write_whole();
  std::string text;
  for (std::size_t k = entries_written_; k < entries_.size(); ++k) text += entry_text(entries_[k]);
  text += pvd_tail;
  const std::uintmax_t offset = bytes_written_ - std::strlen(pvd_tail);
  const int fd = ::open(path_.c_str(), O_WRONLY);
  if (fd < 0) return write_whole();
  const ssize_t n = ::pwrite(fd, text.data(), text.size(), static_cast<off_t>(offset));
  const int error = errno;
  if (n != static_cast<ssize_t>(text.size())) {
    // A full disk: put the old closing tags back over what was written, within the file's old
    // size, so the series stays the valid file of the frames before.
    (void)!::pwrite(fd, pvd_tail, std::strlen(pvd_tail), static_cast<off_t>(offset));
    (void)!::ftruncate(fd, static_cast<off_t>(bytes_written_));
  }
  ::close(fd);
  if (n != static_cast<ssize_t>(text.size()))
    throw InputError(path_ + ": cannot append to the file: " + (n < 0 ? std::string(std::strerror(error)) : std::string("a short write (is the disk full?)")));
  entries_written_ = entries_.size();
  bytes_written_ = offset + text.size();
}

}  // namespace pilelab::dem
