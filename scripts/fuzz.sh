#!/usr/bin/env bash
# Fuzzes every reader of user input (fuzz/: scene files, meshes, dem.h5, fields.h5,
# checkpoints) with libFuzzer under AddressSanitizer and UndefinedBehaviorSanitizer.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 600 s, every target)
#
# Builds with clang into build-fuzz/ (the libraries instrumented, no deal.II), runs each target
# from its corpus fuzz/corpus/TARGET, and then:
#  - inputs that reach new code are merged, minimised, into the corpus of the text formats
#    (scene, mesh), which the test suite replays (fuzz_replay_TARGET); the HDF5 targets' finds
#    stay in build-fuzz/corpus/TARGET (binary files of tens of kB each: not committed);
#  - an input that crashed or escaped its reader is in build-fuzz/crashes/TARGET/; copy it into
#    fuzz/corpus/TARGET/ once fixed, so that the replay test keeps it fixed.
# Exit status: non-zero if any target found a defect.
set -uo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-600}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene mesh dem_file fields checkpoint)
build=$repo/build-fuzz
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (apt-get install clang)" >&2; exit 2; }
cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Release -DPILELAB_FUZZ=ON -DPILELAB_CONTINUUM=OFF -DPILELAB_TESTS=OFF \
  -DPILELAB_BENCHMARKS=OFF -DPILELAB_OPENMP=OFF >/dev/null || exit 2
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}" || exit 2
# Leaks of third-party libraries on refused files are not ours (fuzz/lsan.supp says which).
# A file the probe of common/hdf5_probe.h cannot read in 5 s is refused (the default 60 s would
# exceed the fuzzer's time-out).
export PILELAB_HDF5_PROBE_LIMIT_S=5
export LSAN_OPTIONS=suppressions=$repo/fuzz/lsan.supp:print_suppressions=0
status=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/crashes/$t"
  dict=()
  [[ -f $repo/fuzz/$t.dict ]] && dict=(-dict="$repo/fuzz/$t.dict")
  echo "fuzz: $t for $seconds s" >&2
  # HDF5 prints its error stack for every refused file: only libFuzzer's own lines are kept.
  # gmsh 4.8 leaves a FILE open (4 kB each) for every mesh it refuses: over hundreds of thousands
  # of inputs the mesh target's memory grows by that (one refused mesh ends a pilelab run).
  rss=4096
  [[ $t == mesh ]] && rss=16384
  "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=$rss -print_final_stats=1 \
    -artifact_prefix="$build/crashes/$t/" "${dict[@]}" "$build/corpus/$t" "$repo/fuzz/corpus/$t" \
    > "$build/$t.log" 2>&1 || status=1
  grep -E "^(#[0-9]+.*DONE|stat::number_of_executed_units|stat::peak_rss_mb|==[0-9]+==ERROR|SUMMARY|fuzz $t:)" "$build/$t.log" >&2
  case $t in
    scene | mesh) "$build/fuzz/fuzz_$t" -merge=1 "$repo/fuzz/corpus/$t" "$build/corpus/$t" >/dev/null 2>&1 ;;
  esac
done
# An HDF5 file that crashes HDF5 itself crashes the probe's child process (common/hdf5_probe.h),
# which inherits libFuzzer's handlers and so writes a crash file too, though the reader refused
# the file and the fuzzing went on. Each crash file is run again alone: where the target exits 0,
# the crash was contained in the child, and the file moves to contained/.
for f in "$build"/crashes/*/crash-*; do
  [[ -e $f ]] || continue
  t=$(basename "$(dirname "$f")")
  if "$build/fuzz/fuzz_$t" "$f" >/dev/null 2>&1; then
    mkdir -p "$build/contained/$t"
    mv "$f" "$build/contained/$t/"
  fi
done
for t in "${targets[@]}"; do
  n=$(ls "$build/contained/$t" 2>/dev/null | wc -l)
  ((n)) && echo "fuzz: $t: $n inputs crashed HDF5 in the probe's child and were refused (build-fuzz/contained/$t)" >&2
done
ls "$build"/crashes/*/* >/dev/null 2>&1 && { echo "fuzz: defects found:" >&2; ls "$build"/crashes/*/* >&2; status=1; }
exit $status
