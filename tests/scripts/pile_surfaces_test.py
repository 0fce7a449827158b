#!/usr/bin/python3
"""scripts/pile_surfaces.py on the two small test piles: the figure appears (and no temporary
file stays), one table row per pile, and the ensemble mean is the mean of the runs' own angles;
a flank without a fitted angle (null in report.json) prints n/a and leaves the mean.

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

    # The first pile again, with its right flank unfitted (report.json writes null then).
    unfitted = os.path.join(tmp, "unfitted")
    os.makedirs(unfitted)
    os.symlink(os.path.abspath(os.path.join(piles[0], "dem.h5")), os.path.join(unfitted, "dem.h5"))
    report = json.load(open(os.path.join(piles[0], "report.json")))
    report["dem"]["repose_angle_right_deg"] = None
    json.dump(report, open(os.path.join(unfitted, "report.json"), "w"))
    out = subprocess.run(["/usr/bin/python3", os.path.join(source, "scripts/pile_surfaces.py"), figure, unfitted, piles[1]],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    row = [line for line in out.stdout.splitlines() if line.startswith(unfitted)]
    assert len(row) == 1 and row[0].split()[-1] == "n/a", out.stdout
    match = re.search(r"(\d+) flanks: mean ([0-9.]+) deg", out.stdout)
    assert match and int(match.group(1)) == 3, out.stdout
    left = json.load(open(os.path.join(piles[0], "report.json")))["dem"]["repose_angle_left_deg"]
    expected = (left + angles[2] + angles[3]) / 3
    assert abs(float(match.group(2)) - expected) <= 0.05 + 1e-9, (match.group(2), expected)
print("ok")
