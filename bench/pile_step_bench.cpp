// World steps on a dense pile: particle-steps and contacts per second, by phase.
//
// With PILELAB_BENCH_PILE=path/to/dem.h5 it loads the "settled" snapshot of that file (e.g. the
// paper pile from scenes/paper-symmetric.toml); otherwise it builds a dense heap of 6500 paper
// grains on a plate and lets it fall together for a while first (a minute), and with
// PILELAB_BENCH_SAVE=path/to/heap.h5 it writes that heap there, to be loaded next time.
//
// BM_PourStep steps a pile while it is being poured (grains falling from the funnel, a flowing
// surface), where a pour spends its steps: with PILELAB_BENCH_POUR=DIR it restores
// DIR/checkpoint.h5 of the scene DIR/scene.toml and runs the whole protocol step (world plus
// inflow), e.g. DIR = bench/data/paper_pour_seed1_t35 (the paper pile of seed 1 at t = 35 s:
// 5250 of its 6500 grains poured); without it the benchmark is skipped.
// PILELAB_BENCH_GRAINS=N builds the synthetic heap of N grains instead of 6500 (the extremes'
// 50 000-grain pile), and PILELAB_BENCH_SETTLE_S the time it is let fall together (0.6 s).
// PILELAB_BENCH_SKIN sets the Verlet-list skin (neighbour_skin_fraction; speed only, so a pour's
// checkpoint still continues). Threads: OMP_NUM_THREADS.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <thread>

#include <benchmark/benchmark.h>
#include <omp.h>

#include "common/rng.h"
#include "common/scene_reader.h"
#include "dem/checkpoint.h"
#include "dem/dem_scene.h"
#include "dem/dem_file.h"
#include "dem/grain_generator.h"
#include "dem/snapshot.h"
#include "dem/thread_binding.h"
#include "dem/time_step.h"
#include "dem/world_from_file.h"

using namespace pilelab;
using namespace pilelab::dem;

namespace {
double environment_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text ? std::atof(text) : fallback;
}

WorldSettings paper_settings(Scheme scheme, double stable_limit) {
  WorldSettings s;  // the defaults are the paper's contact law
  s.scheme = scheme;
  s.time_step = 0.8 * stable_limit;
  s.neighbour_skin_fraction = environment_number("PILELAB_BENCH_SKIN", s.neighbour_skin_fraction);
  return s;
}

World synthetic_pile(Scheme scheme) {
  Rng rng(1);
  GrainSpec spec;
  std::vector<Shape> shapes;
  const int grains = static_cast<int>(environment_number("PILELAB_BENCH_GRAINS", 6500));
  for (int i = 0; i < grains; ++i) shapes.push_back(random_grain(spec, rng));
  const double verlet_limit = stable_time_step(shapes, 5000.0, ContactParameters{}, Scheme::verlet).stable_limit;
  World w(paper_settings(Scheme::verlet, verlet_limit));
  // make_polygon centres the shape on its centroid: place it so that its top is y = 0.
  // A triangle of grains on a lattice wider than the largest grain (7.8 mm), like a pile of the
  // paper's size (110 lattice columns either side for 6500 grains), which gravity then packs.
  const int half = grains == 6500 ? 110 : static_cast<int>(std::ceil(1.37 * std::sqrt(double(grains))));
  const double plate = grains == 6500 ? 1.0 : 0.0082 * half + 0.1;
  w.add_wall(make_polygon({{-plate, -0.02}, {plate, -0.02}, {plate, 0.0}, {-plate, 0.0}}), {0, -0.01}, 0.0);
  int placed = 0;
  for (int row = 0; placed < grains; ++row)
    for (int col = -(half - row); col <= half - row && placed < grains; ++col) {
      const int id = w.add_grain(shapes[placed], 5000.0);
      w.activate(id, {0.0082 * col + 0.0041 * (row % 2), 0.0045 + 0.0082 * row}, rng.uniform(0, 2 * M_PI), {0, 0}, 0.0);
      ++placed;
    }
  const double settle = environment_number("PILELAB_BENCH_SETTLE_S", 0.6);
  while (w.time() < settle) w.step();  // let the lattice collapse into a packed heap (cheaply)
  if (const char* path = std::getenv("PILELAB_BENCH_SAVE"))
    write_dem_file(path, "", w, {take_snapshot(w, "settled")}, nlohmann::json::object());
  w.set_time_integration(scheme, 0.8 * stable_time_step(shapes, 5000.0, ContactParameters{}, scheme).stable_limit);
  return w;
}

World load_pile(Scheme scheme) {
  if (const char* path = std::getenv("PILELAB_BENCH_PILE")) {
    const DemFile f = read_dem_file(path);
    std::vector<Shape> grains(f.shapes.begin() + f.wall_count(), f.shapes.end());
    const double density = f.mass.back() / f.shapes.back().area;
    const double limit = stable_time_step(grains, density, ContactParameters{}, scheme).stable_limit;
    return world_from_snapshot(f, "settled", paper_settings(scheme, limit));
  }
  return synthetic_pile(scheme);
}

// Google Benchmark calls the function several times while it sizes the run: prepare each pile
// once and start every call from a copy.
const World& prepared_pile(Scheme scheme) {
  static std::map<Scheme, World> piles;
  auto it = piles.find(scheme);
  if (it == piles.end()) it = piles.emplace(scheme, load_pile(scheme)).first;
  return it->second;
}

// Steps taken before the timing starts: the first builds the pair list of the copied or restored
// pile (and orders its bodies by place), a few milliseconds once, as LAMMPS's setup builds its
// neighbour list before its loop is timed; the others let the threads' shares of the work
// settle (WorkShares). Later list builds fall inside the timed steps as they come.
constexpr int warm_up_steps = 50;

// Each phase's share of the steps' wall time, from the world's profile before and after.
void set_phase_shares(benchmark::State& state, const StepProfile& before, const StepProfile& after) {
  const double total = after.total() - before.total();
  state.counters["share_narrow"] = (after.narrow_phase - before.narrow_phase) / total;
  state.counters["share_broad"] = (after.broad_phase - before.broad_phase) / total;
  state.counters["share_move"] = (after.move - before.move) / total;
  state.counters["share_gather_correct"] = (after.gather_correct - before.gather_correct) / total;
}

void BM_PileStep(benchmark::State& state) {
  const Scheme scheme = static_cast<Scheme>(state.range(0));
  World w = prepared_pile(scheme);
  for (int k = 0; k < warm_up_steps; ++k) w.step();
  const StepProfile before = w.profile();
  std::size_t contacts = 0, candidates = 0, proven_apart = 0;
  for (auto _ : state) {
    w.step();
    contacts += w.contact_count();
    candidates += w.candidate_count();
    proven_apart += w.proven_apart_count();
  }
  const double grains = double(w.active_grains().size());
  state.counters["grains"] = grains;
  state.counters["threads"] = omp_get_max_threads();
  state.counters["cores"] = std::thread::hardware_concurrency();
  state.counters["particle_steps_per_s"] =
      benchmark::Counter(grains * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["contacts_per_s"] = benchmark::Counter(double(contacts), benchmark::Counter::kIsRate);
  state.counters["contacts_per_grain"] = double(contacts) / (grains * double(state.iterations()));
  state.counters["candidates_per_grain"] = double(candidates) / (grains * double(state.iterations()));
  state.counters["proven_apart_per_grain"] = double(proven_apart) / (grains * double(state.iterations()));
  set_phase_shares(state, before, w.profile());
  state.SetLabel(scheme_name(scheme));
}
// The pour from a checkpoint: every call restarts from the same state.
void BM_PourStep(benchmark::State& state) {
  const char* dir = std::getenv("PILELAB_BENCH_POUR");
  if (!dir) {
    state.SkipWithError("set PILELAB_BENCH_POUR=DIR (DIR/scene.toml, DIR/checkpoint.h5)");
    return;
  }
  const std::string scene_path = std::string(dir) + "/scene.toml";
  SceneReader reader = SceneReader::from_file(scene_path);
  DemScene scene = read_dem_scene(reader);
  scene.neighbour_skin_fraction = environment_number("PILELAB_BENCH_SKIN", scene.neighbour_skin_fraction);
  PileProtocol protocol(scene, scene_path);
  RunCounters counters;
  read_checkpoint(std::string(dir) + "/checkpoint.h5", reader.text(), protocol, counters);
  World& w = protocol.world();
  for (int k = 0; k < warm_up_steps; ++k) protocol.step();
  const StepProfile before = w.profile();
  double grain_steps = 0.0;
  std::size_t contacts = 0, candidates = 0, listed = 0, proven_apart = 0;
  const std::int64_t builds_before = w.neighbour_builds();
  for (auto _ : state) {
    protocol.step();
    grain_steps += double(w.active_grains().size());
    contacts += w.contact_count();
    candidates += w.candidate_count();
    proven_apart += w.proven_apart_count();
    listed += w.neighbour_count();
  }
  state.counters["listed_pairs_per_grain"] = double(listed) / grain_steps;
  state.counters["steps_per_list_build"] =
      double(state.iterations()) / std::max<double>(1.0, double(w.neighbour_builds() - builds_before));
  state.counters["grains"] = grain_steps / double(state.iterations());
  state.counters["threads"] = omp_get_max_threads();
  state.counters["particle_steps_per_s"] = benchmark::Counter(grain_steps, benchmark::Counter::kIsRate);
  state.counters["contacts_per_grain"] = double(contacts) / grain_steps;
  state.counters["candidates_per_grain"] = double(candidates) / grain_steps;
  state.counters["proven_apart_per_grain"] = double(proven_apart) / grain_steps;
  set_phase_shares(state, before, w.profile());
  state.SetLabel(scheme_name(protocol.scene().scheme));
}
BENCHMARK(BM_PourStep)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2000);

// Arg: 0 Gear 5, 1 Verlet, 2 leapfrog. Rates per second of wall time (UseRealTime): with threads
// the main thread's CPU time is not the time the step took.
BENCHMARK(BM_PileStep)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
}  // namespace

int main(int argc, char** argv) {
  bind_threads_to_cores();  // as pilelab dem does
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
