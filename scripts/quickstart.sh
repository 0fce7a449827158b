#!/usr/bin/env bash
# Sets up and builds, then runs the quick scene through every stage into out/quick/
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# Every stage of the scene: dem, mesh, coarse, solve, compare, then the figures.
./build/apps/pilelab run scenes/quick.toml -o out/quick
echo "Results in out/quick/: report.json, figures/*.png, dem.pvd, fields.vtu, elastic.vtu, fpa.vtu, compare.vtu (ParaView), profiles.csv"
