#!/usr/bin/python3
"""The signatures study's screen of shapes, construction and base (docs/studies/signatures.md,
part 4): writes one scene per cell of a 2^(6-2) fractional factorial design into
studies/signatures/cells/, from the corrected law's arm of the first screen
(force_point_centroid_spring.toml), so that studies/signatures/screen.py pours them.

    /usr/bin/python3 studies/signatures/design.py [--check]

Six two-level factors, each cell an ensemble of the same 4 seeds (paired across cells), so that
each level of a factor is measured on 32 piles (the first screen's paired differences had a
standard error of 0.5 degrees of repose on 12 pairs; a main effect here averages over 32 piles
per side and is read with the cells' spread):

    A corner placement   jittered 0.25  | random (minimum gap 0.25 of the mean)
    B elongation         axes +-15 %    | +-30 % (the paper's reading, the base's)
    C construction       point source   | uniform rain 0.6 m wide
    D base               flat plate     | a row of immobile grains
    E outlet width       2 grains       | 6 grains (a point source's; a rain has none)
    F drop height        0.25 m         | 0.5 m

A, B, C, D run through all 16 combinations; E = ABC and F = BCD (the defining relation
I = ABCE = BCDF = ADEF, resolution IV). Every main effect is free of two-factor interactions
(aliased only with three-factor ones); the two-factor interactions come in aliased pairs and
cannot be told apart within a pair: AB = CE, AC = BE, AE = BC, AD = EF, AF = DE, BD = CF,
BF = CD (the remaining estimable contrast is ABD = ACF = ...). With a rain (C = +) the outlet
width E does nothing, so E's effect is read from the point-source cells. --check verifies
the design's balance and its aliases and writes nothing.
"""
import argparse
import itertools
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "studies", "paper"))
import stages  # noqa: E402  (scene_with: one key of a TOML table rewritten)

D = 6.8e-3  # the mean grain diameter [m]
SEEDS = 4  # piles a cell
LEVELS = {
    "A": ({"dem.grains": {"corner_placement": '"jittered"', "corner_jitter": "0.25"}},
          {"dem.grains": {"corner_placement": '"random"', "corner_min_gap": "0.25"}}),
    "B": ({"dem.grains": {"polydispersity": "0.15"}}, {"dem.grains": {"polydispersity": "0.3"}}),
    "C": ({"dem.pour": {"kind": '"point_source"'}},
          {"dem.pour": {"kind": '"rain"', "rain_width_m": "0.6", "funnel_walls": "false"}}),
    "D": ({"dem.container": {"base": '"flat"'}}, {"dem.container": {"base": '"grains"'}}),
    "E": ({"dem.pour": {"outlet_width_m": f"{2 * D:.4f}"}}, {"dem.pour": {"outlet_width_m": f"{6 * D:.4f}"}}),
    "F": ({"dem.pour": {"funnel_height_m": "0.25"}}, {"dem.pour": {"funnel_height_m": "0.5"}}),
}


def design():
    """The 16 cells: each a dict factor -> -1 or +1."""
    cells = []
    for a, b, c, d in itertools.product((-1, 1), repeat=4):
        cells.append({"A": a, "B": b, "C": c, "D": d, "E": a * b * c, "F": b * c * d})
    return cells


def check(cells):
    m = np.array([[cell[f] for f in "ABCDEF"] for cell in cells])
    assert (m.sum(axis=0) == 0).all(), "every factor at each level in half the cells"
    assert (m.T @ m == 16 * np.eye(6)).all(), "main effects orthogonal"
    for i, j in itertools.combinations(range(6), 2):  # no main effect aliased with a 2FI
        for k in range(6):
            assert abs((m[:, i] * m[:, j]) @ m[:, k]) == 0, "a main effect aliased with a two-factor interaction"
    return m


def scene(cell, base_text):
    text = base_text
    for factor, level in cell.items():
        for table, keys in LEVELS[factor][(level + 1) // 2].items():
            for key, value in keys.items():
                text = stages.scene_with(text, table, key, value)
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    cells = design()
    check(cells)
    if args.check:
        print("design: 16 cells, balanced, main effects orthogonal and clear of two-factor interactions")
        return
    with open(os.path.join(HERE, "force_point_centroid_spring.toml"), encoding="utf-8") as f:
        base = f.read()
    base = "\n".join(line for line in base.split("\n") if not line.startswith("#"))  # the arm's own header
    base = stages.scene_with(base, "ensemble", "count", str(SEEDS))
    out = os.path.join(HERE, "cells")
    os.makedirs(out, exist_ok=True)
    for k, cell in enumerate(cells, 1):
        levels = " ".join(f"{f}{'+' if v > 0 else '-'}" for f, v in cell.items())
        text = (f"# Cell {k} of the signatures screen of shapes, construction and base (written by\n"
                f"# studies/signatures/design.py, whose docstring gives the factors): {levels}\n" + scene(cell, base))
        text = stages.scene_with(text, "scene", "name", f'"signatures-cell-{k:02d}"')
        text = stages.scene_with(text, "scene", "description", f'"signatures screen, cell {k}: {levels}"')
        path = os.path.join(out, f"cell_{k:02d}.toml")
        with open(path + ".tmp", "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(path + ".tmp", path)
    print(f"design: 16 scenes in {out}")


if __name__ == "__main__":
    main()
