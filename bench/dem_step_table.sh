#!/usr/bin/env bash
# The DEM step's rates for docs/PERFORMANCE.md: bench/pile_step_bench on one pile, each
# integrator (Gear 5, Verlet, leapfrog), on 1 and 2 threads, repeated; prints a Markdown table
# of the minimum and median time per step, particle-steps per second and the phases' shares,
# and one of the two threads' speed-up.
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
# One and two threads alternate, repetition by repetition, so that both sample the same minutes
# of a machine whose speed wanders (docs/PERFORMANCE.md, "The machine").
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for rep in $(seq "$reps"); do
  for threads in 1 2; do
    PILELAB_BENCH_PILE=$pile OMP_NUM_THREADS=$threads "$bench" \
      --benchmark_format=json --benchmark_out="$out/$threads-$rep.json" --benchmark_out_format=json >/dev/null
  done
done
echo "core-to-core round trip after: $(round_trip)"
/usr/bin/python3 - "$out" "$reps" <<'PY'
import json, statistics, sys
out, reps = sys.argv[1], int(sys.argv[2])
names = {"0": "Gear 5", "1": "Verlet", "2": "leapfrog"}
def run(threads, rep, arg):
    for b in json.load(open(f"{out}/{threads}-{rep}.json"))["benchmarks"]:
        if b.get("run_type") == "iteration" and b["name"].startswith(f"BM_PileStep/{arg}/"):
            return b
print("| scheme | threads | ms/step (min, median) | particle-steps/s (best) | contacts/grain | narrow | broad | move | gather+correct |")
print("|---|---|---|---|---|---|---|---|---|")
for threads in (1, 2):
    for arg in ("0", "1", "2"):
        rs = [b for b in (run(threads, rep, arg) for rep in range(1, reps + 1)) if b]
        if not rs:
            continue
        t = [b["real_time"] for b in rs]
        best = min(rs, key=lambda b: b["real_time"])
        print(f"| {names[arg]} | {threads} | {min(t):.3f}, {statistics.median(t):.3f} | {best['particle_steps_per_s']:.3g} | "
              f"{best['contacts_per_grain']:.2f} | {best['share_narrow']:.0%} | {best['share_broad']:.0%} | {best['share_move']:.0%} | "
              f"{best['share_gather_correct']:.0%} |")
print()
print("| scheme | two threads / one: best against best | median of the repetitions' ratios | their range |")
print("|---|---|---|---|")
for arg in ("0", "1", "2"):
    pairs = [(run(1, rep, arg), run(2, rep, arg)) for rep in range(1, reps + 1)]
    ratios = [a["real_time"] / b["real_time"] for a, b in pairs if a and b]
    if not ratios:
        continue
    best = min(a["real_time"] for a, _ in pairs) / min(b["real_time"] for _, b in pairs)
    print(f"| {names[arg]} | {best:.2f} | {statistics.median(ratios):.2f} | {min(ratios):.2f}-{max(ratios):.2f} |")
PY
