// dem.h5 written and read back bit for bit; its errors name the file and the dataset; the VTU
// and PVD files open in meshio (the reader ParaView users script with) when it is installed.
#include "dem/dem_file.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/atomic_file.h"
#include "common/error.h"
#include "common/hdf5_file.h"
#include "dem/snapshot.h"
#include "dem/vtk_writer.h"

namespace pilelab::dem {
namespace {

namespace fs = std::filesystem;

Shape square(double side) {
  const double h = 0.5 * side;
  return make_polygon({{-h, -h}, {h, -h}, {h, h}, {-h, h}});
}

// A floor, a wall moving sideways, three polygons and a disc resting on or pressed into each
// other (so the first steps make contacts of every kind), and a grain never activated.
struct TinyWorld {
  World world{WorldSettings{}};
  std::vector<Snapshot> snapshots;
  std::vector<WallPlacement> walls;

  TinyWorld() {
    Vec2 c;
    const Shape floor = make_polygon({{-0.2, -0.02}, {0.2, -0.02}, {0.2, 0.0}, {-0.2, 0.0}}, &c);
    world.add_wall(floor, c, 0.0);
    world.add_wall(square(0.05), {0.15, 0.1}, 0.3, {0.01, 0.0});  // touches nothing, but moves
    const double rho = 2650.0;
    const int a = world.add_grain(square(0.02), rho);
    const int b = world.add_grain(square(0.02), rho);
    const int t = world.add_grain(make_polygon({{-0.01, 0.0}, {0.01, 0.0}, {0.0, 0.015}}), rho);
    const int d = world.add_grain(make_disc(0.008), rho);
    world.add_grain(square(0.01), rho);  // stays inactive
    world.activate(a, {0.0, 0.0099}, 0.0, {0.0, 0.0}, 0.0);
    world.activate(b, {0.0199, 0.0099}, 0.0, {-0.01, 0.0}, 0.5);
    // The triangle's centroid is 5 mm above its base.
    world.activate(t, {-0.03, 0.0049}, 0.0, {0.0, -0.02}, 0.0);
    world.activate(d, {0.0, 0.0099 + 0.01 + 0.008 - 0.0001}, 0.1, {0.001, 0.0}, -1.0);
    for (int k = 0; k < 5; ++k) world.step();
    capture("settled");
    for (int k = 0; k < 5; ++k) world.step();
    capture("frame_0001");  // written after "settled", though it sorts before it
  }
  void capture(const std::string& name) {
    snapshots.push_back(take_snapshot(world, name));
    walls.push_back(take_wall_placement(world));
  }
};

nlohmann::json run_info() {
  return {{"seed", 42}, {"time_step_s", 1e-6}, {"integrator", "gear5"}, {"settled", true}};
}

// Bit-for-bit equality (== would also call 0.0 and -0.0 equal).
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void expect_same_snapshot(const Snapshot& a, const Snapshot& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_TRUE(same_bits(std::vector<double>{a.time, a.gravity}, std::vector<double>{b.time, b.gravity}));
  EXPECT_TRUE(same_bits(a.body, b.body));
  EXPECT_TRUE(same_bits(a.position, b.position));
  EXPECT_TRUE(same_bits(a.angle, b.angle));
  EXPECT_TRUE(same_bits(a.velocity, b.velocity));
  EXPECT_TRUE(same_bits(a.angular_velocity, b.angular_velocity));
  EXPECT_TRUE(same_bits(a.contact_force, b.contact_force));
  EXPECT_TRUE(same_bits(a.contact_count, b.contact_count));
  EXPECT_TRUE(same_bits(a.pair, b.pair));
  EXPECT_TRUE(same_bits(a.point, b.point));
  EXPECT_TRUE(same_bits(a.normal, b.normal));
  EXPECT_TRUE(same_bits(a.normal_force, b.normal_force));
  EXPECT_TRUE(same_bits(a.tangential_force, b.tangential_force));
  EXPECT_TRUE(same_bits(a.force, b.force));
  EXPECT_TRUE(same_bits(a.overlap_area, b.overlap_area));
  EXPECT_TRUE(same_bits(a.chord, b.chord));
}

// Runs f, which must throw InputError whose message contains every one of the words.
template <class F>
void expect_input_error(F f, const std::vector<std::string>& words) {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    for (const std::string& w : words) EXPECT_NE(std::string(e.what()).find(w), std::string::npos) << e.what();
  }
}

// Edits a copy of a good file with the HDF5 C API, to make the damage the reader must report.
void damage(const std::string& path, const std::function<void(hid_t)>& edit) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  edit(f);
  H5Fclose(f);
}

void delete_dataset(hid_t f, const std::string& name) { ASSERT_GE(H5Ldelete(f, name.c_str(), H5P_DEFAULT), 0); }

class DemFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pilelab_dem_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string written_dem_file(const TinyWorld& t) {
    const std::string path = file("dem.h5");
    write_dem_file(path, scene_, t.world, t.snapshots, t.walls, run_info());
    return path;
  }
  fs::path dir_;
  const std::string scene_ = "# a scene\n[dem]\nseed = 42\nname = \"tiny \\u00e9\"\n";
};

TEST_F(DemFileTest, WorldHasContactsOfEveryKind) {
  TinyWorld t;
  bool wall = false, polygons = false, disc = false;
  for (const Contact& c : t.world.contacts()) {
    wall = wall || t.world.is_wall(c.a);
    const bool da = t.world.shape(c.a).kind == ShapeKind::disc, db = t.world.shape(c.b).kind == ShapeKind::disc;
    disc = disc || da || db;
    polygons = polygons || (!t.world.is_wall(c.a) && !da && !db);
  }
  EXPECT_TRUE(wall);
  EXPECT_TRUE(polygons);
  EXPECT_TRUE(disc);
}

TEST_F(DemFileTest, RoundTripIsBitForBit) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  const DemFile d = read_dem_file(path);

  EXPECT_EQ(d.path, path);
  EXPECT_EQ(d.scene_text, scene_);
  ASSERT_EQ(d.body_count(), t.world.body_count());
  EXPECT_EQ(d.wall_count(), t.world.wall_count());
  for (int i = 0; i < d.body_count(); ++i) {
    const Shape& want = t.world.shape(i);
    const Shape& got = d.shapes[i];
    EXPECT_EQ(got.kind, want.kind);
    ASSERT_EQ(got.vertices.size(), want.vertices.size());
    for (std::size_t k = 0; k < want.vertices.size(); ++k) {
      EXPECT_TRUE(same_bits(std::vector<double>{got.vertices[k].x(), got.vertices[k].y()},
                            std::vector<double>{want.vertices[k].x(), want.vertices[k].y()}));
    }
    EXPECT_TRUE(same_bits(std::vector<double>{got.radius, got.area, got.bounding_radius},
                          std::vector<double>{want.radius, want.area, want.bounding_radius}));
    // Recomputed, not stored: the same formulas, so equal up to the last bits at most.
    EXPECT_NEAR(got.polar_moment, want.polar_moment, 1e-12 * want.polar_moment);
    EXPECT_NEAR(got.inner_radius, want.inner_radius, 1e-12 * want.inner_radius);
    EXPECT_NEAR(got.longest_edge, want.longest_edge, 1e-12 * want.longest_edge);
    EXPECT_EQ(d.is_wall[i], t.world.is_wall(i) ? 1 : 0);
    const bool wall = t.world.is_wall(i);
    EXPECT_TRUE(same_bits(std::vector<double>{d.mass[i], d.moment_of_inertia[i]},
                          std::vector<double>{wall ? 0.0 : t.world.mass(i), wall ? 0.0 : t.world.inertia(i)}));
  }

  ASSERT_EQ(d.snapshot_names, (std::vector<std::string>{"settled", "frame_0001"}));
  for (std::size_t k = 0; k < t.snapshots.size(); ++k) {
    expect_same_snapshot(d.snapshot(d.snapshot_names[k]), t.snapshots[k]);
    const WallPlacement w = d.walls(d.snapshot_names[k]);
    EXPECT_TRUE(same_bits(w.position, t.walls[k].position));
    EXPECT_TRUE(same_bits(w.angle, t.walls[k].angle));
    EXPECT_TRUE(same_bits(w.velocity, t.walls[k].velocity));
  }
  EXPECT_GT(t.snapshots[0].contact_count_total(), 0u);
  EXPECT_EQ(t.snapshots[0].grain_count(), 4u);  // the inactive grain is not in snapshots

  EXPECT_EQ(d.run_int("seed"), 42);
  EXPECT_EQ(d.run_number("time_step_s"), 1e-6);
  EXPECT_EQ(d.run_string("integrator"), "gear5");
  EXPECT_EQ(d.run_int("settled"), 1);

  // Written under a temporary name and renamed: nothing else is left in the directory.
  for (const auto& entry : fs::directory_iterator(dir_)) EXPECT_EQ(entry.path().filename(), "dem.h5");
}

TEST_F(DemFileTest, WallPlacementFromTheWorldNow) {
  TinyWorld t;
  const std::string path = file("dem.h5");
  write_dem_file(path, scene_, t.world, t.snapshots, run_info());
  const DemFile d = read_dem_file(path);
  for (std::size_t k = 0; k < t.snapshots.size(); ++k) {
    const WallPlacement w = d.walls(t.snapshots[k].name);
    // The fixed floor exactly; the moving wall up to rounding of x += v dt.
    EXPECT_TRUE(same_bits(std::vector<double>(w.position.begin(), w.position.begin() + 2),
                          std::vector<double>(t.walls[k].position.begin(), t.walls[k].position.begin() + 2)));
    EXPECT_NEAR(w.position[2], t.walls[k].position[2], 1e-14);
    EXPECT_TRUE(same_bits(w.angle, t.walls[k].angle));
  }
}

TEST_F(DemFileTest, EmptySnapshotListAndNoContacts) {
  World world{WorldSettings{}};
  world.add_grain(make_disc(0.01), 1000.0);
  world.activate(0, {0, 0}, 0, {0, 0}, 0);
  const std::string path = file("dem.h5");
  write_dem_file(path, "", world, {take_snapshot(world, "start")}, nlohmann::json::object());
  DemFile d = read_dem_file(path);
  EXPECT_EQ(d.wall_count(), 0);
  const Snapshot s = d.snapshot("start");
  EXPECT_EQ(s.grain_count(), 1u);
  EXPECT_EQ(s.contact_count_total(), 0u);
  write_dem_file(path, "", world, {}, nlohmann::json::object());
  EXPECT_TRUE(read_dem_file(path).snapshot_names.empty());
}

TEST_F(DemFileTest, BadSnapshotNamesAreRejected) {
  TinyWorld t;
  for (const std::string name : {"", "a,b", "a/b"}) {
    std::vector<Snapshot> s = t.snapshots;
    s[0].name = name;
    EXPECT_THROW(write_dem_file(file("dem.h5"), "", t.world, s, t.walls, run_info()), std::invalid_argument);
  }
  std::vector<Snapshot> twice{t.snapshots[0], t.snapshots[0]};
  EXPECT_THROW(write_dem_file(file("dem.h5"), "", t.world, twice, run_info()), std::invalid_argument);
  EXPECT_FALSE(fs::exists(file("dem.h5")));
}

TEST_F(DemFileTest, MissingFile) {
  const std::string path = file("no_such_dem.h5");
  expect_input_error([&] { read_dem_file(path); }, {path});
}

TEST_F(DemFileTest, NotAnHdf5File) {
  const std::string path = file("garbage.h5");
  std::ofstream(path) << "this is not an HDF5 file\n";
  expect_input_error([&] { read_dem_file(path); }, {path, "HDF5"});
}

TEST_F(DemFileTest, Hdf5FileOfAnotherKind) {
  const std::string path = file("other.h5");
  H5File::create(path).write("/x", std::vector<double>{1.0});
  expect_input_error([&] { read_dem_file(path); }, {path, "format"});
}

TEST_F(DemFileTest, MissingBodyDataset) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  damage(path, [](hid_t f) { delete_dataset(f, "/bodies/mass"); });
  expect_input_error([&] { read_dem_file(path); }, {path, "/bodies/mass"});
}

TEST_F(DemFileTest, MissingSnapshotDataset) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  damage(path, [](hid_t f) { delete_dataset(f, "/snapshots/settled/contacts/normal_force"); });
  const DemFile d = read_dem_file(path);  // snapshots are read on demand
  expect_input_error([&] { d.snapshot("settled"); }, {path, "/snapshots/settled/contacts/normal_force"});
  expect_input_error([&] { d.snapshot("no_such"); }, {path, "no_such"});
  EXPECT_NO_THROW(d.snapshot("frame_0001"));
}

TEST_F(DemFileTest, MissingSnapshotAttribute) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  damage(path, [](hid_t f) { ASSERT_GE(H5Adelete_by_name(f, "/snapshots/settled", "time_s", H5P_DEFAULT), 0); });
  expect_input_error([&] { read_dem_file(path).snapshot("settled"); }, {path, "/snapshots/settled", "time_s"});
}

TEST_F(DemFileTest, WronglyShapedDataset) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  damage(path, [](hid_t f) {
    delete_dataset(f, "/snapshots/settled/position");
    const hsize_t dims[2] = {4, 3};  // (n, 3) instead of (n, 2)
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const std::vector<double> zeros(12, 0.0);
    const hid_t ds = H5Dcreate2(f, "/snapshots/settled/position", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT,
                                H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, zeros.data());
    H5Dclose(ds);
    H5Sclose(space);
  });
  expect_input_error([&] { read_dem_file(path).snapshot("settled"); },
                     {path, "/snapshots/settled/position", "(4, 3)", "(4, 2)"});
}

// A NaN or an infinity anywhere in the physical data is refused with the dataset and the row,
// and a grain's mass must be positive: damage must never flow on into fields as NaN.
TEST_F(DemFileTest, NonFiniteAndNonPositiveValuesAreNamedWithTheirRow) {
  const auto overwrite_value = [](hid_t f, const char* dataset, hsize_t index, double value) {
    const hid_t ds = H5Dopen2(f, dataset, H5P_DEFAULT);
    ASSERT_GE(ds, 0) << dataset;
    const hid_t space = H5Dget_space(ds);
    hsize_t dims[2] = {0, 1};
    const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
    std::vector<double> v(dims[0] * (rank == 2 ? dims[1] : 1));
    ASSERT_LT(index, v.size()) << dataset;
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    v[index] = value;
    H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(space);
    H5Dclose(ds);
  };
  struct Case {
    const char* dataset;
    hsize_t index;
    double value;
    std::vector<std::string> expected;
    bool in_snapshot;
  };
  TinyWorld t;
  const int last_body = t.world.body_count() - 1;  // a grain (walls come first)
  const std::vector<Case> cases = {
      {"/bodies/mass", hsize_t(last_body), NAN, {"/bodies/mass", "row " + std::to_string(last_body), "NaN"}, false},
      {"/bodies/mass", hsize_t(last_body), -1.0, {"/bodies/mass", "row " + std::to_string(last_body), "positive"}, false},
      {"/bodies/moment_of_inertia", hsize_t(last_body), 0.0, {"/bodies/moment_of_inertia", "positive"}, false},
      {"/snapshots/settled/position", 3, NAN, {"/snapshots/settled/position", "row 1, column 1", "NaN"}, true},
      {"/snapshots/settled/position", 0, INFINITY, {"/snapshots/settled/position", "row 0, column 0", "infinite"}, true},
      {"/snapshots/settled/contacts/force", 2, NAN, {"/snapshots/settled/contacts/force", "row 1, column 0"}, true}};
  for (const Case& c : cases) {
    const std::string path = written_dem_file(t);
    damage(path, [&](hid_t f) { overwrite_value(f, c.dataset, c.index, c.value); });
    std::vector<std::string> expected = c.expected;
    expected.insert(expected.begin(), path);
    if (c.in_snapshot)
      expect_input_error([&] { read_dem_file(path).snapshot("settled"); }, expected);
    else
      expect_input_error([&] { read_dem_file(path); }, expected);
  }
}

// A snapshot's attributes are physical values too, and its grains are each named once: an
// infinite gravity or a grain listed twice is refused here, not written on into fields.h5
// (where the next stage would blame fields.h5).
TEST_F(DemFileTest, NonFiniteAttributesAndRepeatedGrainsAreRefused) {
  TinyWorld t;
  {
    const std::string path = written_dem_file(t);
    damage(path, [](hid_t f) {
      // Replaced, not overwritten in place: the same attribute, now infinite.
      ASSERT_GE(H5Adelete_by_name(f, "/snapshots/settled", "gravity_m_per_s2", H5P_DEFAULT), 0);
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t a = H5Acreate_by_name(f, "/snapshots/settled", "gravity_m_per_s2", H5T_NATIVE_DOUBLE, space,
                                        H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      ASSERT_GE(a, 0);
      const double infinite = INFINITY;
      EXPECT_GE(H5Awrite(a, H5T_NATIVE_DOUBLE, &infinite), 0);
      H5Aclose(a);
      H5Sclose(space);
    });
    expect_input_error([&] { read_dem_file(path).snapshot("settled"); },
                       {path, "/snapshots/settled", "gravity_m_per_s2", "infinite"});
  }
  {
    const std::string path = written_dem_file(t);
    damage(path, [](hid_t f) {
      const hid_t ds = H5Dopen2(f, "/snapshots/settled/body", H5P_DEFAULT);
      ASSERT_GE(ds, 0);
      const hid_t space = H5Dget_space(ds);
      std::vector<std::int64_t> body(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
      H5Sclose(space);
      ASSERT_GE(body.size(), 2u);
      H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, body.data());
      body[1] = body[0];
      H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, body.data());
      H5Dclose(ds);
    });
    expect_input_error([&] { read_dem_file(path).snapshot("settled"); }, {path, "/snapshots/settled/body", "row 1", "a second time"});
  }
}

TEST_F(DemFileTest, VertexOffsetsMustMatchVertices) {
  TinyWorld t;
  const std::string path = written_dem_file(t);
  damage(path, [&](hid_t f) {
    // One vertex more for the last body than /bodies/vertices holds.
    std::vector<std::int64_t> offset(t.world.body_count() + 1);
    const hid_t ds = H5Dopen2(f, "/bodies/vertex_offset", H5P_DEFAULT);
    H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, offset.data());
    offset.back() += 1;
    H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, offset.data());
    H5Dclose(ds);
  });
  expect_input_error([&] { read_dem_file(path); }, {path, "/bodies/vertices", "shape"});
}

// --- VTU / PVD --------------------------------------------------------------------------

std::string slurp(const std::string& path) { return read_text_file(path); }

// A series grown frame by frame is appended in place (the file keeps its inode: it is not
// rewritten and renamed each frame), holds after every frame exactly the bytes a whole write of
// the same entries gives, and is written whole again when changed behind its back.
TEST_F(DemFileTest, PvdSeriesGrowsInPlace) {
  PvdSeries grown(file("grown.pvd"));
  struct stat first {};
  for (int k = 0; k < 50; ++k) {
    const double time = 1e-3 * k + 1.0 / 3.0;
    const std::string name = "grains_" + std::to_string(k) + ".vtu";
    grown.add(time, name, 0, "grains");
    grown.write();
    PvdSeries whole(file("whole.pvd"));
    for (int j = 0; j <= k; ++j) whole.add(1e-3 * j + 1.0 / 3.0, "grains_" + std::to_string(j) + ".vtu", 0, "grains");
    whole.write();
    ASSERT_EQ(slurp(file("grown.pvd")), slurp(file("whole.pvd"))) << "after frame " << k;
    struct stat now {};
    ASSERT_EQ(::stat(file("grown.pvd").c_str(), &now), 0);
    if (k == 0) first = now;
    EXPECT_EQ(now.st_ino, first.st_ino) << "frame " << k << " rewrote the file instead of appending";
  }
  std::ofstream(file("grown.pvd"), std::ios::app) << "<!-- edited -->\n";
  grown.add(1.0, "grains_50.vtu", 0, "grains");
  grown.write();
  EXPECT_EQ(slurp(file("grown.pvd")).find("edited"), std::string::npos);
  EXPECT_NE(slurp(file("grown.pvd")).find("grains_50.vtu\"/>\n  </Collection>\n</VTKFile>\n"), std::string::npos);
}

TEST_F(DemFileTest, VtuAndPvdFiles) {
  TinyWorld t;
  const std::string dem = written_dem_file(t);
  fs::create_directories(dir_ / "vtk");
  const std::string grains = file("vtk/grains_0000.vtu"), contacts = file("vtk/contacts_0000.vtu");
  const std::string walls = file("vtk/walls_0000.vtu");
  write_grains_vtu(grains, t.world);
  write_contacts_vtu(contacts, t.world);
  write_walls_vtu(walls, t.world);

  World lonely{WorldSettings{}};  // no contacts at all
  lonely.add_grain(make_disc(0.01), 1000.0);
  lonely.activate(0, {0, 0}, 0, {0, 0}, 0);
  const std::string empty = file("vtk/contacts_empty.vtu");
  write_contacts_vtu(empty, lonely);
  EXPECT_NE(slurp(empty).find("NumberOfCells=\"0\""), std::string::npos);

  PvdSeries pvd(file("dem.pvd"));
  pvd.add(t.world.time(), "vtk/grains_0000.vtu", 0, "grains");
  pvd.add(t.world.time(), "vtk/contacts_0000.vtu", 1, "contacts");
  pvd.add(t.world.time(), "vtk/walls_0000.vtu", 2, "walls");
  pvd.write();
  EXPECT_EQ(pvd.size(), 3u);
  const std::string text = slurp(file("dem.pvd"));
  EXPECT_NE(text.find("type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("file=\"vtk/contacts_0000.vtu\""), std::string::npos);

  const int cells = static_cast<int>(t.world.active_grains().size());
  const int lines = static_cast<int>(t.world.contacts().size());
  ASSERT_GT(lines, 0);
  if (std::system("/usr/bin/python3 -c 'import meshio, h5py' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with meshio and h5py is not available";
  const std::string script = std::string(PILELAB_SOURCE_DIR) + "/tests/dem/read_vtk_with_meshio.py";
  auto quote = [](const std::string& s) { return "'" + s + "'"; };
  const std::string command = "/usr/bin/python3 " + quote(script) + " " + quote(dem) + " " + quote(grains) + " " +
                              std::to_string(cells) + " " + quote(contacts) + " " + std::to_string(lines) + " " +
                              quote(empty) + " " + quote(file("dem.pvd")) + " " + quote(walls) + " " +
                              std::to_string(t.world.wall_count());
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << command;
  EXPECT_EQ(WEXITSTATUS(status), 0) << command;
}

}  // namespace
}  // namespace pilelab::dem
