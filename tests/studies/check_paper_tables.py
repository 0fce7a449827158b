#!/usr/bin/python3
"""Checks the paper study's tables and figures (studies/paper/tables.py):

    check_paper_tables.py DOC FIGURE_DIR

- the tables between the markers have a section for each ensemble, each with its findings
  table (five columns) and its table of the models against the DEM;
- every measured value in the findings ("ours", and "ours" at the RVE study's size) and every
  model-minus-DEM difference is a finite number with its standard error ("v ± se"); the only
  cells without one are those that say why (the RVE study's range of sizes, the models' own
  base profiles, the fit's 95 % intervals);
- every figure of the paper with data behind it was written.
Exits 1 naming each failure.
"""
import math
import os
import re
import sys

SECTIONS = ("Symmetric piles", "Asymmetric piles", "Monodisperse piles")
FIGURES = ("fig05_rve_strain", "fig06_rve_fabric", "fig07_volume_fraction", "fig08_fabric", "fig09_stress",
           "fig11_asymmetric_stress", "fig12_displacement", "fig13_strain", "fig14_strain_orientation",
           "fig15_misalignment", "fig16a_fabric_trace_monodisperse", "fig16b_fabric_trace",
           "fig17_fabric_trace_volume_fraction")
NUMBER = r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?"
WITH_ERROR = re.compile(rf"^{NUMBER} ± {NUMBER}$")
# Findings whose cell is not a statistic with an error, and says what it is instead.
NO_ERROR_FINDINGS = ("RVE size at which",)


def cells(line):
    parts = re.split(r"(?<!\\)\|", line.strip())[1:-1]
    return [p.strip() for p in parts]


def main():
    doc, figure_dir = sys.argv[1:3]
    text = open(doc, encoding="utf-8").read()
    m = re.search(r"<!-- table: studies/paper/tables.py -->\n(.*?)<!-- end of table -->", text, re.S)
    failures = []
    if not m:
        sys.exit(f"{doc}: no tables between the markers")
    tables = m.group(1)
    sections = re.split(r"^### ", tables, flags=re.M)[1:]
    found = [s.split("\n", 1)[0] for s in sections]
    for name in SECTIONS:
        if not any(f.startswith(name) for f in found):
            failures.append(f"no section '{name}' (found: {found})")
    for section in sections:
        title = section.split("\n", 1)[0]
        rows = [cells(l) for l in section.splitlines() if l.startswith("|") and not l.startswith("|---")]
        findings = [r for r in rows if len(r) == 5 and r[0] != "finding"]
        models = [r for r in rows if len(r) == 3 and r[0] != "model"]
        if len(findings) < 3:
            failures.append(f"{title}: {len(findings)} findings rows")
        if not any("relative L2" in r[1] for r in models):
            failures.append(f"{title}: no model-minus-DEM differences")
        for finding, _, ours, ours_rve, _ in findings:
            if finding.startswith(NO_ERROR_FINDINGS):
                continue
            for label, cell in (("ours", ours), ("ours at the RVE study's size", ours_rve)):
                for value in cell.split(" / "):
                    if not WITH_ERROR.match(value):
                        failures.append(f"{title}: '{finding}', {label}: '{value}' is not a number with its error")
                    elif not all(math.isfinite(float(x)) for x in value.split(" ± ")):
                        failures.append(f"{title}: '{finding}', {label}: '{value}' is not finite")
        for model, quantity, value in models:
            if "relative L2" in quantity or "angle between" in quantity:
                if not WITH_ERROR.match(value) or not all(math.isfinite(float(x)) for x in value.split(" ± ")):
                    failures.append(f"{title}: {model} {quantity}: '{value}' is not a finite number with its error")
    for name in FIGURES:
        path = os.path.join(figure_dir, name + ".png")
        if not os.path.exists(path) or os.path.getsize(path) < 1000:
            failures.append(f"figure {path} missing or empty")
    for f in failures:
        print("check_paper_tables:", f)
    if failures:
        sys.exit(1)
    print(f"check_paper_tables: {len(sections)} sections, {len(FIGURES)} figures: ok")


if __name__ == "__main__":
    main()
