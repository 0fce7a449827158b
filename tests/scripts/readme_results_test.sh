#!/usr/bin/env bash
# README's "Results on the quick scene" are this build's: the quick scene run here (same scene
# and seed, same files) gives exactly the numbers README states (scripts/readme_results.py).
#   bash tests/scripts/readme_results_test.sh REPO PILELAB OUT
set -euo pipefail
repo=$1 pilelab=$2 out=$3
rm -rf "$out"
"$pilelab" run "$repo/scenes/quick.toml" -o "$out" -q --no-figures
/usr/bin/python3 "$repo/scripts/readme_results.py" --check "$out"
