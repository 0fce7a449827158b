#!/usr/bin/env bash
# Sets up and builds, then pours the bundled quick scene into out/quick/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
./build/apps/pilelab dem scenes/quick.toml -o out/quick
./build/apps/pilelab mesh scenes/quick.toml -o out/quick
./build/apps/pilelab coarse scenes/quick.toml -o out/quick
/usr/bin/python3 scripts/figures.py out/quick
echo "Results in out/quick/: report.json, dem.h5, dem.pvd, pile.msh, fields.vtu (open in ParaView), profiles.csv, figures/*.png"
