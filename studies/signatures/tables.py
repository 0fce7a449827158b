#!/usr/bin/python3
"""The signatures study's tables and figures from its committed products alone
(docs/studies/signatures/data/<arm>/members.json and base.json, written by screen.py):

    /usr/bin/python3 studies/signatures/tables.py [--doc docs/studies/signatures.md]

The 2 x 2 screen crosses the force point (the overlap's centroid against the chord's midpoint)
with the tangential history (the spring alone against the whole force stored). Its arms share
their seeds, so every effect is paired: per seed, the contrast of the arms' values, then the
mean and standard error over seeds (for the ensemble's field statistics, which exist only for
the mean fields, the jackknife over seeds of the contrast of the arms' leave-one-out values). A
main effect is the mean over the other factor's two levels; the interaction is half the
difference of one factor's effect at the other's two levels. An effect counts beyond 2 SE. The
tables go between the markers <!-- screen:begin --> and <!-- screen:end --> of the doc; the
figure to docs/studies/signatures/screen.png.
"""
import argparse
import json
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(ROOT, "docs", "studies", "signatures", "data")
sys.path.insert(0, os.path.join(ROOT, "studies", "paper"))
from tables import jackknife_se  # noqa: E402  (the paper study's jackknife)

# (arm, force point, history)
ARMS = [("force_point_centroid_spring", "centroid", "spring"), ("force_point_centroid", "centroid", "total"),
        ("force_point_midpoint_spring", "midpoint", "spring"), ("force_point_midpoint", "midpoint", "total")]
# Per-pile responses: (key, label, decimals)
PILE = [("repose_mean_deg", "repose angle, mean of the flanks [deg]", 2),
        ("height_m", "height [m]", 4),
        ("plate_force_dip", "plate load: centre \\|x'\\| < 0.1 over ring 0.15-0.35, minus 1", 3),
        ("kinetic_energy_final_J", "kinetic energy at the end [J]", None),
        ("lost", "grains lost", 2)]
# Ensemble field statistics from base.json (run.py's), with leave-one-out values.
FIELDS = [("volume_fraction_core", "core volume fraction", 4),
          ("fabric_trace_core", "core fabric trace", 3),
          ("stress_anisotropy_core", "core stress anisotropy", 3),
          ("stress_tilt_flanks_deg", "stress tilt on the flanks [deg]", 2),
          ("base_centre_over_max", "coarse sigma_yy at y = 0: centre over maximum", 3)]


def load_arm(arm):
    d = os.path.join(DATA, arm)
    if not os.path.exists(os.path.join(d, "members.json")):
        return None
    with open(os.path.join(d, "members.json"), encoding="utf-8") as f:
        members = {m["seed"]: m for m in json.load(f)["members"]}
    for m in members.values():
        left, right = m["repose_angle_left_deg"], m["repose_angle_right_deg"]
        m["repose_mean_deg"] = 0.5 * (left + right) if left is not None and right is not None else None
    with open(os.path.join(d, "base.json"), encoding="utf-8") as f:
        base = json.load(f)
    return {"members": members, "base": base}


def value(m, key):
    v = m.get(key)
    return np.nan if v is None else float(v)


def pile_stats(arm, key):
    v = np.array([value(m, key) for m in arm["members"].values()])
    v = v[np.isfinite(v)]
    return v.mean(), v.std(ddof=1) / np.sqrt(len(v)), len(v)


def paired(arms, key, weights):
    """sum_k w_k x_k per seed over the arms, its mean and standard error over the seeds."""
    seeds = sorted(set.intersection(*[set(a["members"]) for a in arms]))
    c = np.array([sum(w * value(a["members"][s], key) for a, w in zip(arms, weights)) for s in seeds])
    c = c[np.isfinite(c)]
    return c.mean(), c.std(ddof=1) / np.sqrt(len(c)), len(c)


def paired_fields(arms, key, weights):
    """The contrast of the arms' ensemble statistic and its jackknife error over the seeds they
    share (each arm's leave-one-out value with the same seed left out)."""
    seeds = [a["base"]["seeds"] for a in arms]
    if any(s != seeds[0] for s in seeds):
        raise ValueError("the arms' ensembles do not share their seeds in order")
    v = sum(w * a["base"]["quantities"][key][0] for a, w in zip(arms, weights))
    loo = sum(w * np.array(a["base"]["leave_one_out"][key]) for a, w in zip(arms, weights))
    return v, float(jackknife_se(loo[:, None])[0]), len(loo)


def fmt(v, s, d):
    """v ± s with d decimals; in scientific notation where d is None or v is below 10^-d."""
    return f"{v:.{d}f} ± {s:.{d}f}" if d is not None and (abs(v) >= 10 ** -d or v == 0) else f"{v:.2e} ± {s:.1e}"


def verdict(v, s):
    return "beyond 2 SE" if abs(v) > 2 * s else "within 2 SE"


def build_tables(arms):
    lines = []
    n = len(next(iter(arms.values()))["members"])
    lines += [f"Arms ({n} paired seeds each, 1600 grains, leapfrog at 0.8 of the limit; mean ± standard error over piles):", "",
              "| response | " + " | ".join(f"{fp}, {h}" for _, fp, h in ARMS) + " |",
              "|---|" + "---|" * len(ARMS)]
    for key, label, d in PILE:
        lines.append(f"| {label} | " + " | ".join(fmt(*pile_stats(arms[a], key)[:2], d) for a, _, _ in ARMS) + " |")
    for key, label, d in FIELDS:
        cells = []
        for a, _, _ in ARMS:
            q = arms[a]["base"]["quantities"][key]
            cells.append(fmt(q[0], q[1], d))
        lines.append(f"| {label} (jackknife) | " + " | ".join(cells) + " |")
    # Effects: weights over ARMS' order (cs, ct, ms, mt).
    effects = [("force point: centroid - midpoint", [0.5, 0.5, -0.5, -0.5]),
               ("history: spring - total", [0.5, -0.5, 0.5, -0.5]),
               ("interaction (half the difference of the force point's effects)", [0.5, -0.5, -0.5, 0.5]),
               ("the new law against the old: centroid, spring - midpoint, total", [1, 0, 0, -1])]
    ordered = [arms[a] for a, _, _ in ARMS]
    lines += ["", "Paired effects (mean ± standard error over seeds; verdict at 2 SE):", "",
              "| response | " + " | ".join(e for e, _ in effects) + " |", "|---|" + "---|" * len(effects)]
    rows = [(key, label, d, paired) for key, label, d in PILE] + [(key, label, d, paired_fields) for key, label, d in FIELDS]
    for key, label, d, contrast in rows:
        cells = [f"{fmt(v, s, d)} ({verdict(v, s)})" for v, s, _ in (contrast(ordered, key, w) for _, w in effects)]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def figure(arms, path):
    os.environ.setdefault("MATPLOTLIBRC", "/usr/share/matplotlib/mpl-data/matplotlibrc")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    for a, fp, h in ARMS:
        profiles = [m["plate_load_over_weight_per_R"] for m in arms[a]["members"].values()
                    if m.get("plate_load_over_weight_per_R")]
        x = next(m["plate_load_x_over_R"] for m in arms[a]["members"].values() if m.get("plate_load_x_over_R"))
        p = np.array(profiles)
        mean, se = p.mean(axis=0), p.std(axis=0, ddof=1) / np.sqrt(len(p))
        line, = ax.plot(x, mean, label=f"{fp}, {h} ({len(p)} piles)")
        ax.fill_between(x, mean - se, mean + se, color=line.get_color(), alpha=0.2)
    ax.set_xlim(-1.3, 1.3)
    ax.set_xlabel("x' = (x - x_apex) / R")
    ax.set_ylabel("plate load / weight per unit x'")
    ax.set_title("The plate's load (mean ± SE over piles)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=8)
    ordered = [arms[a] for a, _, _ in ARMS]
    names = ["force point\n(centroid - midpoint)", "history\n(spring - total)", "interaction"]
    weights = [[0.5, 0.5, -0.5, -0.5], [0.5, -0.5, 0.5, -0.5], [0.5, -0.5, -0.5, 0.5]]
    for k, (key, label) in enumerate([("repose_mean_deg", "repose angle [deg]"), ("plate_force_dip", "plate dip x 10")]):
        scale = 10 if key == "plate_force_dip" else 1
        vs = [paired(ordered, key, w) for w in weights]
        bx.errorbar(np.arange(3) + 0.15 * (k - 0.5), [scale * v[0] for v in vs], yerr=[2 * scale * v[1] for v in vs],
                    fmt="o", capsize=4, label=label + " (± 2 SE)")
    bx.axhline(0, color="k", lw=0.8)
    bx.set_xticks(range(3))
    bx.set_xticklabels(names, fontsize=8)
    bx.set_title("Paired main effects and interaction")
    bx.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, fontsize=8)
    fig.text(0.01, 0.01, "1600-grain piles, 1 core per pile", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--doc", default=os.path.join(ROOT, "docs", "studies", "signatures.md"))
    args = parser.parse_args()
    arms = {a: load_arm(a) for a, _, _ in ARMS}
    missing = [a for a, v in arms.items() if v is None]
    if missing:
        text = "Not yet measured: " + ", ".join(missing) + " (studies/signatures/screen.py pours them)."
    else:
        text = build_tables(arms)
        figure(arms, os.path.join(ROOT, "docs", "studies", "signatures", "screen.png"))
    with open(args.doc, encoding="utf-8") as f:
        doc = f.read()
    new = re.sub(r"(<!-- screen:begin -->\n).*?(\n<!-- screen:end -->)", lambda m: m.group(1) + text + m.group(2), doc,
                 flags=re.S)
    if new == doc and "<!-- screen:begin -->" not in doc:
        sys.exit(f"tables.py: {args.doc} has no <!-- screen:begin --> marker")
    with open(args.doc + ".tmp", "w", encoding="utf-8") as f:
        f.write(new)
    os.replace(args.doc + ".tmp", args.doc)


if __name__ == "__main__":
    main()
