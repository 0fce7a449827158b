#!/usr/bin/env bash
# The DEM step's rates for docs/PERFORMANCE.md: bench/pile_step_bench on one pile, each
# integrator (Gear 5, Verlet, leapfrog), on 1 and 2 threads, repeated; prints a Markdown table
# of the minimum and median time per step, particle-steps per second and the phases' shares.
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
echo "pile: $pile; $(nproc) cores: $(lscpu | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1); load $(cut -d ' ' -f 1 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC'); pilelab $(git -C "$repo" rev-parse --short HEAD)"
for threads in 1 2; do
  PILELAB_BENCH_PILE=$pile OMP_NUM_THREADS=$threads "$bench" --benchmark_repetitions="$reps" \
    --benchmark_format=json --benchmark_out=/tmp/pilelab-bench-$threads.json --benchmark_out_format=json >/dev/null
done
/usr/bin/python3 - "$reps" <<'PY'
import json, statistics, sys
names = {"0": "Gear 5", "1": "Verlet", "2": "leapfrog"}
print("| scheme | threads | ms/step (min, median) | particle-steps/s (best) | contacts/grain | narrow | broad | move | gather+correct |")
print("|---|---|---|---|---|---|---|---|---|")
for threads in (1, 2):
    runs = [b for b in json.load(open(f"/tmp/pilelab-bench-{threads}.json"))["benchmarks"] if b.get("run_type") == "iteration"]
    for arg in ("0", "1", "2"):
        rs = [b for b in runs if b["name"].startswith(f"BM_PileStep/{arg}/")]
        if not rs:
            continue
        t = [b["real_time"] for b in rs]
        best = min(rs, key=lambda b: b["real_time"])
        print(f"| {names[arg]} | {threads} | {min(t):.3f}, {statistics.median(t):.3f} | {best['particle_steps_per_s']:.3g} | "
              f"{best['contacts_per_grain']:.2f} | {best['share_narrow']:.0%} | {best['share_broad']:.0%} | {best['share_move']:.0%} | "
              f"{best['share_gather_correct']:.0%} |")
PY
