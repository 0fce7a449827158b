#!/usr/bin/env bash
# Throughput of pilelab against LAMMPS on a dense 2D pile of about 6500 polygons (README.md).
#
#   bash bench/peers/compare.sh [path/to/pile_step_bench]
#
# Runs, one after the other (never two at a time): the LAMMPS pile's settling (not timed), the
# LAMMPS timed block with 1 and 2 MPI ranks, then pilelab's pile_step_bench (Verlet,
# BM_PileStep/1) with OMP_NUM_THREADS=1 and 2. Prints the machine, the date and a table of
# particle-steps per second, per core, and pilelab / LAMMPS per core.
#
# Environment (all optional):
#   LMP=lmp                LAMMPS executable
#   COUNTS="1 2"           MPI ranks and OpenMP threads to compare
#   LAMMPS_STEPS=2000      steps of the timed LAMMPS block
#   LAMMPS_SETTLE_MS=150   settling before it [ms of simulated time]
#   LAMMPS_DT=0.02         time step [ms]
#   LAMMPS_SETTLED=file    start the timed blocks from this settled data file (skips settling)
#   BENCH_ARGS=...         extra arguments for pile_step_bench (e.g. --benchmark_repetitions=3)
#   PEERS_WORK=dir         working directory (default: a new /tmp/pilelab-peers.XXXXXX)
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
bench=${1:-$repo/build/bench/pile_step_bench}
py=/usr/bin/python3
LMP=${LMP:-lmp}
COUNTS=${COUNTS:-"1 2"}
steps=${LAMMPS_STEPS:-2000}
settle_ms=${LAMMPS_SETTLE_MS:-150}
dt=${LAMMPS_DT:-0.02}

echo "pilelab vs LAMMPS: dense 2D pile of rounded / sharp polygons"
echo "date:    $(date -u '+%Y-%m-%d %H:%M:%S UTC')"
cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)
sockets=$(lscpu 2>/dev/null | sed -n 's/^Socket(s):[[:space:]]*//p' | head -n 1)
per_socket=$(lscpu 2>/dev/null | sed -n 's/^Core(s) per socket:[[:space:]]*//p' | head -n 1)
cores=$(( ${sockets:-1} * ${per_socket:-$(nproc)} ))
cpus=$(nproc)
echo "machine: ${cpu:-unknown CPU}; $cores cores, $cpus CPUs available; $(uname -sr)"
load=$(cut -d ' ' -f 1 /proc/loadavg 2>/dev/null || echo 0)
echo "load:    $load (1-minute average before the runs)"
if [ -x "$repo/build/bench/core_round_trip" ]; then
  echo "cores:   $("$repo/build/bench/core_round_trip") ns a cache line's round trip between the first two (bench/core_round_trip.cpp)"
fi
if "$py" -c "import sys; sys.exit(0 if float('$load') > 0.5 else 1)" 2>/dev/null; then
  echo "warning: the machine is not idle; the rates below share it with other work"
fi
echo "pilelab: $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo '?')$(git -C "$repo" diff --quiet HEAD 2>/dev/null || echo ' (with local changes)')"

if ! command -v "$LMP" >/dev/null 2>&1; then
  echo
  echo "LAMMPS ('$LMP') is not installed, so there is nothing to compare against."
  echo "On Debian or Ubuntu:  sudo apt-get install lammps   (it brings the BODY package this"
  echo "benchmark needs); or set LMP to another LAMMPS executable. Skipping the comparison."
  exit 0
fi

work=${PEERS_WORK:-$(mktemp -d /tmp/pilelab-peers.XXXXXX)}
mkdir -p "$work"
cd "$work"
echo "LAMMPS:  $("$LMP" -h 2>/dev/null | sed -n 's/^Large-scale Atomic\/Molecular Massively Parallel Simulator - //p' | head -n 1) ($(command -v "$LMP"))"
echo "work:    $work"

mpi=()
if command -v mpirun >/dev/null 2>&1; then
  mpi=(mpirun)
  if [ "$(id -u)" = 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    mpi+=(--allow-run-as-root)
  fi
fi

# lammps RANKS LOG ARGS...: one LAMMPS run on RANKS MPI ranks, one OpenMP thread each.
lammps() {
  local ranks=$1 log=$2
  shift 2
  local cmd=("$LMP" -in "$here/pile.in" -log "$log" -screen none "$@")
  if [ ${#mpi[@]} -gt 0 ]; then
    cmd=("${mpi[@]}" -np "$ranks" "${cmd[@]}")
  elif [ "$ranks" != 1 ]; then
    echo "no mpirun: cannot run LAMMPS on $ranks ranks" >&2
    return 1
  fi
  if ! OMP_NUM_THREADS=1 "${cmd[@]}" >"$log.out" 2>&1; then
    echo "LAMMPS failed: ${cmd[*]}" >&2
    tail -n 20 "$log" "$log.out" >&2 || true
    return 1
  fi
}

# loop_line LOG: the 'Loop time of X on P procs for N steps with M atoms' line of the timed block.
loop_line() {
  awk '/^PILE timed block/ {timed = 1} timed && /^Loop time of/ {print; exit}' "$1"
}

max_count=1
for n in $COUNTS; do
  if [ "$n" -gt "$max_count" ]; then max_count=$n; fi
done
settle_ranks=$(( max_count < cpus ? max_count : cpus ))

echo
if [ -n "${LAMMPS_SETTLED:-}" ]; then
  settled=$LAMMPS_SETTLED
  echo "LAMMPS: timed blocks start from $settled (no settling)"
else
  "$py" "$here/make_lammps_pile.py" -o pile.data
  echo "LAMMPS: settling $settle_ms ms at dt = $dt ms on $settle_ranks rank(s) (not timed) ..."
  lammps "$settle_ranks" settle.log -var data pile.data -var dt "$dt" -var settle "$settle_ms" \
    -var steps 0 -var write 1 -var settled settled.data
  settled=$work/settled.data
  awk '/^Loop time of/ {print "  settling: " $0}' settle.log
fi
"$py" "$here/lammps_contacts.py" "$settled" | sed 's/^/  /'

declare -A lmp_rate pl_rate
for n in $COUNTS; do
  if [ "$n" -gt "$cpus" ]; then
    echo "  $n ranks: skipped, only $cpus CPUs"
    continue
  fi
  echo "LAMMPS: timed block of $steps steps on $n rank(s) ..."
  lammps "$n" "lammps_np$n.log" -var data "$settled" -var dt "$dt" -var settle 0 -var steps "$steps"
  line=$(loop_line "lammps_np$n.log")
  if [ -z "$line" ]; then
    echo "  no 'Loop time' line for the timed block in $work/lammps_np$n.log" >&2
    exit 1
  fi
  # Loop time of X on P procs for N steps with M atoms
  read -r secs procs nsteps atoms <<<"$(echo "$line" | awk '{print $4, $6, $9, $12}')"
  if [ "$procs" != "$n" ]; then
    echo "  warning: LAMMPS ran on $procs procs, not $n" >&2
  fi
  lmp_rate[$n]=$(awk -v m="$atoms" -v s="$nsteps" -v t="$secs" 'BEGIN {printf "%.6g", m * s / t}')
  neigh=$(awk '/^PILE timed block/ {timed = 1} timed && /^Ave neighs\/atom/ {print $4; exit}' "lammps_np$n.log")
  echo "  $line -> ${lmp_rate[$n]} particle-steps/s (neighbour-list pairs per body: $neigh)"
  # The last thermo line of the timed block: step time ke temp/body pe vmax ymin ymax atoms.
  awk '/^PILE timed block/ {timed = 1} timed && $1 == "Step" {table = 1; next}
       table && /^Loop time/ {exit} table && NF == 9 {last = $0}
       END {split(last, f); printf "  at its end: kinetic energy %.4g J, elastic energy %.4g J, " \
            "fastest grain %.3g m/s, highest centre %.1f mm, %d bodies\n", f[3] / 1000, f[5] / 1000, f[6], f[8], f[9];
            if (f[6] > 2.0) print "  warning: a grain moves faster than 2 m/s; the pile may have exploded"}' \
    "lammps_np$n.log"
done

# pilelab: Google Benchmark's JSON lists the runs under "benchmarks", each with its counters as
# fields (particle_steps_per_s, a rate over the run's CPU time, and grains, threads, ...).
echo
if [ ! -x "$bench" ]; then
  echo "pilelab: no benchmark program at $bench (build it: cmake --build build --target pile_step_bench);"
  echo "         pass its path as the argument to compare.sh. Only the LAMMPS rates are shown."
else
  for n in $COUNTS; do
    if [ "$n" -gt "$cpus" ]; then
      echo "  $n threads: skipped, only $cpus CPUs"
      continue
    fi
    echo "pilelab: pile_step_bench BM_PileStep/1 (Verlet) with OMP_NUM_THREADS=$n ..."
    # shellcheck disable=SC2086
    if ! OMP_NUM_THREADS=$n "$bench" --benchmark_filter=BM_PileStep/1 --benchmark_format=json \
        ${BENCH_ARGS:-} >"pilelab_t$n.json" 2>"pilelab_t$n.err"; then
      echo "pile_step_bench failed; see $work/pilelab_t$n.err" >&2
      tail -n 20 "pilelab_t$n.err" >&2 || true
      exit 1
    fi
    read -r rate wall label threads grains contacts <<<"$("$py" - "pilelab_t$n.json" <<'EOF'
import json, sys
text = open(sys.argv[1]).read()
try:
    doc = json.loads(text)
except ValueError:  # anything printed before the JSON object
    doc = json.loads(text[text.index("\n{") + 1:] if not text.startswith("{") else text)
runs = [b for b in doc.get("benchmarks", [])
        if b.get("name", "").startswith("BM_PileStep/1") and b.get("run_type", "iteration") == "iteration"
        and not b.get("error_occurred", False)]
if not runs:
    sys.exit("no BM_PileStep/1 run in " + sys.argv[1])
unit = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
rates = sorted(b["particle_steps_per_s"] for b in runs)
walls = sorted(b["grains"] / (b["real_time"] * unit[b.get("time_unit", "ns")]) for b in runs)
mid = len(runs) // 2  # the median over repetitions
print("%.6g %.6g %s %d %d %.3f" % (rates[mid], walls[mid], runs[0].get("label", "?"),
      runs[0].get("threads", 0), runs[0].get("grains", 0), runs[0].get("contacts_per_grain", 0.0)))
EOF
)"
    pl_rate[$n]=$rate
    echo "  $grains grains, scheme $label, $threads OpenMP thread(s): $rate particle-steps/s" \
         "(touching pairs per grain: $contacts)"
    if awk -v a="$rate" -v b="$wall" 'BEGIN {exit !(a > 1.05 * b || a < 0.95 * b)}'; then
      echo "  note: over wall-clock time it made $wall particle-steps/s (the counter divides by the" \
           "main thread's CPU time)"
    fi
  done
fi

echo
printf '%-8s %14s %18s %14s %24s\n' code ranks/threads particle-steps/s "per core" "pilelab/LAMMPS per core"
for n in $COUNTS; do
  if [ -n "${lmp_rate[$n]:-}" ]; then
    printf '%-8s %14s %18.4g %14.4g %24s\n' LAMMPS "$n" "${lmp_rate[$n]}" \
      "$(awk -v r="${lmp_rate[$n]}" -v n="$n" 'BEGIN {print r / n}')" ""
  fi
done
for n in $COUNTS; do
  if [ -n "${pl_rate[$n]:-}" ]; then
    ratio=""
    if [ -n "${lmp_rate[$n]:-}" ]; then
      ratio=$(awk -v p="${pl_rate[$n]}" -v l="${lmp_rate[$n]}" 'BEGIN {printf "%.2f", p / l}')
    fi
    printf '%-8s %14s %18.4g %14.4g %24s\n' pilelab "$n" "${pl_rate[$n]}" \
      "$(awk -v r="${pl_rate[$n]}" -v n="$n" 'BEGIN {print r / n}')" "$ratio"
  fi
done
echo
echo "LAMMPS: particle-steps/s = bodies x timed steps / loop time (its 'Loop time' line); dt = $dt ms."
echo "pilelab: the particle_steps_per_s counter of BM_PileStep/1. Logs and data in $work."
