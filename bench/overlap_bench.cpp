// Narrow-phase and contact-law kernels: overlaps per second for the shapes of the paper.
#include <vector>

#include <benchmark/benchmark.h>

#include "common/rng.h"
#include "dem/contact_law.h"
#include "dem/convex_overlap.h"
#include "dem/grain_generator.h"

using namespace pilelab;
using namespace pilelab::dem;

namespace {
struct PlacedPair {
  std::vector<Vec2> a, b;
  Vec2 ca, cb;
  double ra = 0, rb = 0;
};

// Pairs of paper grains (6-8 corners, 30 % polydispersity) placed so that their bounding
// circles overlap, as the broad phase hands them over: some touch, some do not.
std::vector<PlacedPair> paper_pairs(ShapeKind kind, int n) {
  Rng rng(42);
  GrainSpec spec;
  spec.kind = kind;
  std::vector<PlacedPair> pairs;
  for (int i = 0; i < n; ++i) {
    const Shape sa = random_grain(spec, rng), sb = random_grain(spec, rng);
    PlacedPair p;
    p.ca = {0, 0};
    const double dist = (sa.bounding_radius + sb.bounding_radius) * rng.uniform(0.75, 1.0);
    const double phi = rng.uniform(0, 2 * M_PI);
    p.cb = dist * Vec2(std::cos(phi), std::sin(phi));
    const double ta = rng.uniform(0, 2 * M_PI), tb = rng.uniform(0, 2 * M_PI);
    for (const Vec2& v : sa.vertices) p.a.push_back(p.ca + rotate(v, std::cos(ta), std::sin(ta)));
    for (const Vec2& v : sb.vertices) p.b.push_back(p.cb + rotate(v, std::cos(tb), std::sin(tb)));
    p.ra = sa.radius;
    p.rb = sb.radius;
    pairs.push_back(std::move(p));
  }
  return pairs;
}

void BM_PolygonOverlap(benchmark::State& state) {
  const auto pairs = paper_pairs(ShapeKind::polygon, 1024);
  std::size_t k = 0, touching = 0;
  for (auto _ : state) {
    const PlacedPair& p = pairs[k++ & 1023];
    const Overlap o = overlap_polygons(p.a.data(), int(p.a.size()), p.ca, p.b.data(), int(p.b.size()), p.cb);
    touching += o.touching();
    benchmark::DoNotOptimize(o);
  }
  state.counters["pairs_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["touching_fraction"] = double(touching) / double(state.iterations());
}
BENCHMARK(BM_PolygonOverlap);

// The same pairs as contacts that persist: each keeps the hint its last evaluation left, as
// the World does from one step to the next (the pairs here do not move, the best case).
void BM_PolygonOverlapWithHint(benchmark::State& state) {
  const auto pairs = paper_pairs(ShapeKind::polygon, 1024);
  std::vector<OverlapHint> hints(pairs.size());
  std::size_t k = 0, touching = 0;
  for (auto _ : state) {
    const std::size_t q = k++ & 1023;
    const PlacedPair& p = pairs[q];
    const Overlap o = overlap_polygons(p.a.data(), int(p.a.size()), p.ca, p.b.data(), int(p.b.size()), p.cb,
                                       0.01, hints[q]);
    touching += o.touching();
    benchmark::DoNotOptimize(o);
  }
  state.counters["pairs_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["touching_fraction"] = double(touching) / double(state.iterations());
}
BENCHMARK(BM_PolygonOverlapWithHint);

void BM_DiscOverlap(benchmark::State& state) {
  const auto pairs = paper_pairs(ShapeKind::disc, 1024);
  std::size_t k = 0;
  for (auto _ : state) {
    const PlacedPair& p = pairs[k++ & 1023];
    benchmark::DoNotOptimize(overlap_discs(p.ca, p.ra, p.cb, p.rb));
  }
  state.counters["pairs_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DiscOverlap);

void BM_ContactLaw(benchmark::State& state) {
  ContactParameters law;
  ContactKinematics k{1e-7, 3e-3, 3e-3, 3e-3, 0.01, 0.02, 0.1, 0.05};
  double spring = 0.0;
  for (auto _ : state) {
    const ContactForce f = contact_force(law, k, contact_length(law, k.lever_a, k.lever_b), spring, 1e-6);
    spring = f.spring;
    benchmark::DoNotOptimize(f);
  }
  state.counters["contacts_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ContactLaw);
}  // namespace

BENCHMARK_MAIN();
