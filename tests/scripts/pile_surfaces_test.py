#!/usr/bin/python3
"""scripts/pile_surfaces.py on the two small test piles: the figure appears (and no temporary
file stays), one table row per pile, and the ensemble mean is the mean of the runs' own angles.

    pile_surfaces_test.py SOURCE_DIR PILE_A PILE_B
"""
import json
import os
import re
import subprocess
import sys
import tempfile

source, piles = sys.argv[1], sys.argv[2:]
with tempfile.TemporaryDirectory() as tmp:
    figure = os.path.join(tmp, "surfaces.png")
    out = subprocess.run(["/usr/bin/python3", os.path.join(source, "scripts/pile_surfaces.py"), figure, *piles],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert os.path.getsize(figure) > 0, "no figure"
    assert not os.path.exists(figure + ".tmp.png"), "temporary figure left behind"
    rows = [line for line in out.stdout.splitlines() if any(line.startswith(p) for p in piles)]
    assert len(rows) == len(piles), out.stdout

    angles = []
    for p in piles:
        report = json.load(open(os.path.join(p, "report.json")))["dem"]
        angles += [report["repose_angle_left_deg"], report["repose_angle_right_deg"]]
    match = re.search(r"(\d+) flanks: mean ([0-9.]+) deg", out.stdout)
    assert match, out.stdout
    assert int(match.group(1)) == len(angles)
    # The script prints one decimal: it must agree with the reports' mean to within its rounding.
    assert abs(float(match.group(2)) - sum(angles) / len(angles)) <= 0.05 + 1e-9, (match.group(2), angles)
print("ok")
