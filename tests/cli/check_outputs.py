#!/usr/bin/python3
"""Opens every output of `pilelab run` with readers pilelab did not write (h5py, meshio, json,
csv) and checks that report.json has every key docs/FORMAT.md documents for the sections given.

usage: check_outputs.py OUT FORMAT.md SECTION...   (exit 1 with a list of problems)
"""
import csv
import json
import os
import re
import sys

import h5py
import meshio

out, format_md, sections = sys.argv[1], sys.argv[2], sys.argv[3:]
problems = []


def check(condition, message):
    if not condition:
        problems.append(message)


# Files open with independent readers.
for name in ("dem.h5", "fields.h5") + (("models.h5",) if "continuum" in sections else ()):
    with h5py.File(os.path.join(out, name), "r") as f:
        check(len(list(f.keys())) > 0, f"{name}: empty")
with h5py.File(os.path.join(out, "fields.h5"), "r") as f:
    check(f["fields/stress_yy"].attrs["unit"] in (b"N/m", "N/m"), "fields.h5: stress_yy has no unit N/m")
for name in ("pile.msh", "fields.vtu", "compare.vtu"):
    m = meshio.read(os.path.join(out, name))
    check(len(m.points) > 0 and len(m.cells) > 0, f"{name}: no points or cells")
for name in ("profiles.csv", "rve_study.csv"):
    with open(os.path.join(out, name)) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) > 0, f"{name}: no rows")
    if name == "profiles.csv":
        sources = {r["source"] for r in rows}
        check("dem" in sources, "profiles.csv: no dem rows")
        if "continuum" in sections:
            check({"elastic", "fpa"} <= sources, f"profiles.csv: model rows missing, sources {sources}")
figures = os.path.join(out, "figures")
for png in ("pile_pressure.png", "force_network.png", "base_pressure.png", "sigma_yy_profiles.png",
            "orientations.png", "rve_convergence.png", "fit_scatter.png"):
    check(os.path.getsize(os.path.join(figures, png)) > 1000, f"figures/{png} missing or empty")

# report.json has every documented key of each section.
report = json.load(open(os.path.join(out, "report.json")))
text = open(format_md).read()
region = text[text.index("## report.json"):]
documented = {}
for match in re.finditer(r"^### (?:report\.json: )?`(\w+)`\n(.*?)(?=^#|\Z)", text, re.S | re.M):
    name, body = match.group(1), match.group(2)
    if match.start() < text.index("## report.json") and "report.json" not in match.group(0):
        continue
    keys = []
    for line in body.splitlines():
        first = line.split("|")[1] if line.startswith("|") else ""
        if ":" in first or not first.strip().startswith("`"):
            continue
        # A key only a build with the continuum module writes (FORMAT.md says so in its row).
        if "with the continuum module" in line and "continuum" not in sections:
            continue
        keys += re.findall(r"`(\w+)`", first)
    documented.setdefault(name, keys)
for section in sections:
    check(section in report, f"report.json: no section '{section}'")
    check(section in documented and documented[section], f"FORMAT.md documents no keys for '{section}'")
    for key in documented.get(section, []):
        check(key in report.get(section, {}), f"report.json: '{section}' lacks documented key '{key}'")

if problems:
    print("\n".join(problems))
    sys.exit(1)
print("all outputs open; report keys as documented:", ", ".join(sections))
