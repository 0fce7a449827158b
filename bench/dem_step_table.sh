#!/usr/bin/env bash
# The DEM step's rates for docs/PERFORMANCE.md: bench/pile_step_bench on one pile, each
# integrator (Gear 5, Verlet, leapfrog), on 1 and 2 threads, repeated; prints a Markdown table
# of the minimum and median time per step, particle-steps per second and the phases' shares,
# on one thread (on each core) and two, and one of the two threads' speed-up.
# Run it alone on the machine (nothing else on the cores).
#
#   bash bench/dem_step_table.sh [PILE.h5] [REPETITIONS]
#
# PILE.h5: a dem.h5 whose "settled" snapshot is stepped (default: the synthetic dense heap the
# bench builds, saved to /tmp/pilelab-bench-heap.h5 on first use).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bench=$repo/build/bench/pile_step_bench
pile=${1:-/tmp/pilelab-bench-heap.h5}
reps=${2:-5}
if [ ! -f "$pile" ]; then
  echo "building the synthetic heap into $pile (about a minute)" >&2
  PILELAB_BENCH_SAVE=$pile OMP_NUM_THREADS=1 "$bench" --benchmark_filter='BM_PileStep/1/' --benchmark_min_time=0.01 >/dev/null
fi
# The cores' round trip before and after (bench/core_round_trip.cpp): about 100 ns where the two
# share a cache, several hundred where they do not, which the two-thread rates feel.
round_trip() { [ -x "$repo/build/bench/core_round_trip" ] && echo "$("$repo/build/bench/core_round_trip") ns" || echo "not built"; }
echo "core-to-core round trip before: $(round_trip)"
echo "pile: $pile; $(nproc) cores: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1); load $(cut -d ' ' -f 1 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC'); pilelab $(git -C "$repo" rev-parse --short HEAD)"
# One thread on each core and two threads alternate, repetition by repetition, so that all
# sample the same minutes of a machine whose speed wanders. On a virtual machine one core can run
# this step far slower than the other for minutes at a time (its cache shared with another
# guest's work; docs/PERFORMANCE.md, "The machine"), which bounds what two threads can reach:
# the speed-ups are given for all repetitions and for those in which the two cores ran one
# thread within 5 % of each other.
cores=$(nproc)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for rep in $(seq "$reps"); do
  for run in 1c0 1c1 2; do
    case $run in
      1c0) threads=1 places="{0}" ;;
      1c1) [ "$cores" -ge 2 ] || continue; threads=1 places="{1}" ;;
      2) threads=2 places="{0},{1}" ;;
    esac
    PILELAB_BENCH_PILE=$pile OMP_NUM_THREADS=$threads OMP_PROC_BIND=true OMP_PLACES=$places "$bench" \
      --benchmark_format=json --benchmark_out="$out/$run-$rep.json" --benchmark_out_format=json >/dev/null
  done
done
echo "core-to-core round trip after: $(round_trip)"
/usr/bin/python3 - "$out" "$reps" <<'PY'
import json, os, statistics, sys
out, reps = sys.argv[1], int(sys.argv[2])
names = {"0": "Gear 5", "1": "Verlet", "2": "leapfrog"}
runs = {"1c0": "1 (core 0)", "1c1": "1 (core 1)", "2": "2"}
def run(name, rep, arg):
    path = f"{out}/{name}-{rep}.json"
    if not os.path.exists(path):
        return None
    for b in json.load(open(path))["benchmarks"]:
        if b.get("run_type") == "iteration" and b["name"].startswith(f"BM_PileStep/{arg}/"):
            return b
print("| scheme | threads | ms/step (min, median) | particle-steps/s (best) | contacts/grain | narrow | broad | move | gather+correct |")
print("|---|---|---|---|---|---|---|---|---|")
for name in runs:
    for arg in ("0", "1", "2"):
        rs = [b for b in (run(name, rep, arg) for rep in range(1, reps + 1)) if b]
        if not rs:
            continue
        t = [b["real_time"] for b in rs]
        best = min(rs, key=lambda b: b["real_time"])
        print(f"| {names[arg]} | {runs[name]} | {min(t):.3f}, {statistics.median(t):.3f} | {best['particle_steps_per_s']:.3g} | "
              f"{best['contacts_per_grain']:.2f} | {best['share_narrow']:.0%} | {best['share_broad']:.0%} | {best['share_move']:.0%} | "
              f"{best['share_gather_correct']:.0%} |")
print()
print("Two threads against one thread on core 0: best against best; the median and range of each repetition's ratio; "
      "the same over the repetitions whose one-thread runs on the two cores agreed within 5 %.")
print()
print("| scheme | best against best | median (range) | cores agreed in | best against best there | median there |")
print("|---|---|---|---|---|---|")
for arg in ("0", "1", "2"):
    reps_ = [(run("1c0", r, arg), run("1c1", r, arg), run("2", r, arg)) for r in range(1, reps + 1)]
    reps_ = [x for x in reps_ if x[0] and x[2]]
    if not reps_:
        continue
    ratio = lambda x: x[0]["real_time"] / x[2]["real_time"]
    ratios = [ratio(x) for x in reps_]
    best = min(x[0]["real_time"] for x in reps_) / min(x[2]["real_time"] for x in reps_)
    even = [x for x in reps_ if x[1] and abs(x[1]["real_time"] / x[0]["real_time"] - 1) <= 0.05]
    if even:
        even_best = min(x[0]["real_time"] for x in even) / min(x[2]["real_time"] for x in even)
        there = f"{even_best:.2f} | {statistics.median(ratio(x) for x in even):.2f}"
    else:
        there = "- | -"
    print(f"| {names[arg]} | {best:.2f} | {statistics.median(ratios):.2f} ({min(ratios):.2f}-{max(ratios):.2f}) | "
          f"{len(even)} of {len(reps_)} | {there} |")
PY
