#!/usr/bin/python3
"""The signatures study's second screen (shapes, construction, base): the main effects of its six
factors and its estimable two-factor interaction chains, from the committed products of its 16
cells alone (docs/studies/signatures/data/cells/cell_XX/{members,base}.json, written by screen.py).

    /usr/bin/python3 studies/signatures/factorial.py [--doc docs/studies/signatures.md]

The design is studies/signatures/design.py's 2^(6-2) fraction (resolution IV: E = ABC, F = BCD),
each cell an ensemble of the same seeds. A pile's responses are its own (repose angle, height,
the plate load's dip statistic, grains lost) and, for the fields that exist only for a cell's mean
(the core's volume fraction, ...), its jackknife pseudo-value n theta - (n - 1) theta_(i), whose
mean over the cell is the jackknife estimate and whose spread gives the jackknife error. An
effect is the mean over the piles of the cells at + minus that at -, its standard error
s sqrt(1/n+ + 1/n-) with s the pooled within-cell standard deviation (the cells' own spread, so
a factor that changes the spread does not fake precision). It counts beyond 2 SE. With fewer than
16 cells in, the design is not balanced: the cells' means are listed and no effect is computed.
The tables go between <!-- screen2:begin --> and <!-- screen2:end --> of the doc.
"""
import argparse
import json
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(ROOT, "docs", "studies", "signatures", "data", "cells")
sys.path.insert(0, HERE)
import design  # noqa: E402  (the cells' factor levels)

FACTORS = {"A": "corner placement: random - jittered", "B": "elongation: +-30 % - +-15 %",
           "C": "construction: rain - point source", "D": "base: grains - flat plate",
           "E": "outlet: 6 - 2 grains wide", "F": "drop height: 0.5 - 0.25 m"}
# The two-factor interaction chains the design can estimate (each pair aliased with the other).
CHAINS = ["AB=CE", "AC=BE", "AD=EF", "AE=BC", "AF=DE", "BD=CF", "BF=CD"]
PILE = [("repose_mean_deg", "repose angle [deg]", 2), ("height_m", "height [m]", 4),
        ("plate_force_dip", "plate-load dip statistic", 3), ("lost", "grains lost", 1)]
FIELDS = [("volume_fraction_core", "core volume fraction", 4), ("base_centre_over_max", "coarse base centre / max", 3)]


def load_cells():
    cells = []
    for k, levels in enumerate(design.design(), 1):
        d = os.path.join(DATA, f"cell_{k:02d}")
        if not os.path.exists(os.path.join(d, "members.json")):
            cells.append(None)
            continue
        with open(os.path.join(d, "members.json"), encoding="utf-8") as f:
            members = sorted(json.load(f)["members"], key=lambda m: m["seed"])
        with open(os.path.join(d, "base.json"), encoding="utf-8") as f:
            base = json.load(f)
        if [m["seed"] for m in members] != base["seeds"]:
            raise ValueError(f"{d}: members.json and base.json list other seeds")
        rows = []
        n = len(members)
        for i, m in enumerate(members):
            left, right = m["repose_angle_left_deg"], m["repose_angle_right_deg"]
            row = {"repose_mean_deg": 0.5 * (left + right) if left is not None and right is not None else np.nan}
            for key, _, _ in PILE[1:]:
                row[key] = np.nan if m.get(key) is None else float(m[key])
            for key, _, _ in FIELDS:
                theta, loo = base["quantities"][key][0], base["leave_one_out"][key][i]
                row[key] = n * theta - (n - 1) * loo if theta is not None and loo is not None else np.nan
            rows.append(row)
        cells.append({"levels": levels, "rows": rows})
    return cells


def column(cells, key):
    """Per pile: the response, its cell index, and each factor's level."""
    y, cell, levels = [], [], []
    for k, c in enumerate(cells):
        for r in c["rows"]:
            y.append(r[key])
            cell.append(k)
            levels.append(c["levels"])
    return np.array(y), np.array(cell), levels


def contrast(y, cell, signs):
    ok = np.isfinite(y)
    y, cell, signs = y[ok], cell[ok], signs[ok]
    plus, minus = y[signs > 0], y[signs < 0]
    # Pooled within-cell variance: each cell's spread about its own mean.
    resid = np.concatenate([y[cell == k] - y[cell == k].mean() for k in np.unique(cell)])
    dof = len(y) - len(np.unique(cell))
    s2 = (resid ** 2).sum() / dof if dof > 0 else np.nan
    return plus.mean() - minus.mean(), np.sqrt(s2 * (1 / len(plus) + 1 / len(minus)))


def fmt(v, s, d):
    return f"{v:+.{d}f} ± {s:.{d}f}" + (" **(> 2 SE)**" if abs(v) > 2 * s else "")


def build(cells):
    done = [c for c in cells if c is not None]
    lines = [f"{len(done)} of 16 cells poured ({sum(len(c['rows']) for c in done)} piles of 1600 grains)."]
    lines += ["", "Cell means (piles' mean; the fields' jackknife estimate):", "",
              "| cell | levels | " + " | ".join(label for _, label, _ in PILE + FIELDS) + " |",
              "|---|---|" + "---|" * (len(PILE) + len(FIELDS))]
    for k, c in enumerate(cells, 1):
        if c is None:
            continue
        levels = " ".join(f"{f}{'+' if v > 0 else '-'}" for f, v in c["levels"].items())
        means = [np.nanmean([r[key] for r in c["rows"]]) for key, _, _ in PILE + FIELDS]
        lines.append(f"| {k} | {levels} | " + " | ".join(f"{m:.{d}f}" for m, (_, _, d) in zip(means, PILE + FIELDS)) + " |")
    if len(done) < 16:
        lines += ["", "The effects wait for all 16 cells: with cells missing the design is not balanced and the "
                  "factors are not separated."]
        return "\n".join(lines)
    lines += ["", "Main effects and two-factor interaction chains (mean over the piles at + minus at -; ± the "
              "standard error from the pooled within-cell spread):", "",
              "| effect | " + " | ".join(label for _, label, _ in PILE + FIELDS) + " |",
              "|---|" + "---|" * (len(PILE) + len(FIELDS))]
    effects = [(f"{f}: {FACTORS[f]}", lambda lv, f=f: lv[f]) for f in "ABCDEF"]
    effects += [(chain, lambda lv, a=chain[0], b=chain[1]: lv[a] * lv[b]) for chain in CHAINS]
    for name, sign_of in effects:
        cells_text = []
        for key, _, d in PILE + FIELDS:
            y, cell, levels = column(done, key)
            cells_text.append(fmt(*contrast(y, cell, np.array([sign_of(lv) for lv in levels], dtype=float)), d))
        lines.append(f"| {name} | " + " | ".join(cells_text) + " |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--doc", default=os.path.join(ROOT, "docs", "studies", "signatures.md"))
    args = parser.parse_args()
    text = build(load_cells())
    with open(args.doc, encoding="utf-8") as f:
        doc = f.read()
    if "<!-- screen2:begin -->" not in doc:
        print(text)
        sys.exit(f"factorial.py: {args.doc} has no <!-- screen2:begin --> ... <!-- screen2:end --> markers")
    doc = re.sub(r"<!-- screen2:begin -->.*?<!-- screen2:end -->",
                 lambda _: "<!-- screen2:begin -->\n" + text + "\n<!-- screen2:end -->", doc, flags=re.S)
    with open(args.doc + ".tmp", "w", encoding="utf-8") as f:
        f.write(doc)
    os.replace(args.doc + ".tmp", args.doc)
    print(text)


if __name__ == "__main__":
    main()
