#!/usr/bin/python3
"""Does a moving funnel make an asymmetric pile, and how fast must it move? (docs/studies/funnel_scan.md)

    /usr/bin/python3 studies/funnel_scan/run.py [-P PROCESSES] [--out DIR] [--pilelab BIN]
    /usr/bin/python3 studies/funnel_scan/run.py --table     # table and figure from the committed CSV only

The paper's asymmetric piles (section 5) were poured from a funnel moved "slowly" to the right
and came out 28 degrees on the left and 21 on the right; ours, with the funnel travelling 0.35 of
the base half-width, show no asymmetry (docs/studies/paper.md). The paper gives neither the
speed nor the travel, so this scans them: piles of scenes/paper-asymmetric.toml's grains and
contact law, 800 grains each (a pour of 8 s at 100 grains/s), with the funnel moving during the
whole pour over a travel of 0, 0.25, 0.35 (as in paper-asymmetric.toml), 0.5, 0.75, 1 and 2 times
the fixed-funnel pile's base half-width R (about 0.25 m), centred on the plate. Each travel is
an ensemble of the same 6 seeds, poured by `pilelab run` (resumable: members already poured are
kept). Every member's angles go to docs/studies/funnel_scan/angles.csv, from which --table
prints the table of the study's doc and draws docs/studies/funnel_scan/angles.png.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "studies", "paper"))
import stages  # noqa: E402  (scene_with: one key of a scene rewritten)
import tables as paper_tables  # noqa: E402  (replace_between_markers)

CSV = os.path.join(ROOT, "docs", "studies", "funnel_scan", "angles.csv")
DOC = os.path.join(ROOT, "docs", "studies", "funnel_scan.md")
GRAINS, RATE = 800, 100.0  # a pour of GRAINS / RATE = 8 s
POUR_TIME_S = GRAINS / RATE
HALF_WIDTH_M = 0.25        # base half-width of the 800-grain pile from a fixed funnel
TRAVELS = [0.0, 0.5, 1.0, 2.0, 0.35, 0.25, 0.75]  # over HALF_WIDTH_M; 0.35: paper-asymmetric.toml's
SEEDS = 6
FIELDS = ["travel_over_R", "funnel_speed_m_per_s", "seed", "repose_angle_left_deg", "repose_angle_right_deg",
          "height_m", "apex_x_m", "lost"]


def scene_text(travel):
    """paper-asymmetric.toml's DEM (grains, contact law, funnel height and rate) with 800 grains,
    the funnel moving right over travel * HALF_WIDTH_M during the pour, no later stage."""
    with open(os.path.join(ROOT, "scenes", "paper-asymmetric.toml"), encoding="utf-8") as f:
        text = f.read()
    text = text[:text.index("\n[mesh]")] + "\n"  # the DEM only: the angles are what is measured
    travel_m = travel * HALF_WIDTH_M
    speed = travel_m / POUR_TIME_S
    for table, key, value in [
        ("scene", "name", f'"funnel-scan-{travel:g}"'),
        ("ensemble", "count", str(SEEDS)),
        ("dem", "grain_count", str(GRAINS)),
        ("dem.pour", "rate_grains_per_s", repr(RATE)),
        ("dem.pour", "funnel_x_m", repr(-0.5 * travel_m)),
        ("dem.pour", "funnel_speed_m_per_s", repr(speed)),
        ("dem.pour", "funnel_travel_m", repr(travel_m)),
        ("dem.relax", "enabled", "false"),          # no gravity change: only the angles are kept
        ("dem.output", "frame_interval_s", "100.0"),  # no frames
    ]:
        text = stages.scene_with(text, table, key, value)
    return text, speed


def run(args):
    rows = []
    for travel in TRAVELS:
        directory = os.path.join(args.out, f"travel_{travel:g}")
        os.makedirs(directory, exist_ok=True)
        text, speed = scene_text(travel)
        scene = os.path.join(directory, "scene.toml")
        with open(scene + ".tmp", "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(scene + ".tmp", scene)
        print(f"run.py: travel {travel:g} R (funnel {speed:.4f} m/s)", flush=True)
        # --allow-unsettled: every pile is measured, an unfit one recorded in the report's status.
        subprocess.run([args.pilelab, "run", scene, "-o", directory, "-P", str(args.processes), "-j", "1",
                        "--no-figures", "-q", "--allow-unsettled"], check=True,
                       env=dict(os.environ, OMP_WAIT_POLICY="passive"))
        with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
            members = json.load(f)["ensemble"]["members"]
        for m in members:
            with open(os.path.join(directory, m["directory"], "report.json"), encoding="utf-8") as f:
                dem = json.load(f)["dem"]
            rows.append({"travel_over_R": travel, "funnel_speed_m_per_s": speed, "seed": m["seed"],
                         "repose_angle_left_deg": m["repose_angle_left_deg"],
                         "repose_angle_right_deg": m["repose_angle_right_deg"], "height_m": m["height_m"],
                         "apex_x_m": dem["apex_x_m"], "lost": m["lost"]})
        write_csv(rows)  # after every travel, so that a stopped scan keeps what it measured
    table()
    figure()


def write_csv(rows):
    os.makedirs(os.path.dirname(CSV), exist_ok=True)
    with open(CSV + ".tmp", "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(CSV + ".tmp", CSV)


def mean_se(values):
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else float("nan")
    return mean, sd / math.sqrt(n)


def table():
    """The study's table, printed and written into docs/studies/funnel_scan.md between its
    markers: per travel, the mean angles and their difference (left minus right, paired within
    each pile) with one standard error over the piles."""
    with open(CSV, encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    lines = ["| funnel travel / R | funnel speed (m/s) | piles | left (deg) | right (deg) | left - right (deg) | apex x (m) |",
             "|---|---|---|---|---|---|---|"]
    for travel in sorted({float(r["travel_over_R"]) for r in rows}):
        rs = [r for r in rows if float(r["travel_over_R"]) == travel]
        left = [float(r["repose_angle_left_deg"]) for r in rs]
        right = [float(r["repose_angle_right_deg"]) for r in rs]
        cells = [mean_se(left), mean_se(right), mean_se([a - b for a, b in zip(left, right)]),
                 mean_se([float(r["apex_x_m"]) for r in rs])]
        text = [f"{m:.1f} ± {s:.1f}" for m, s in cells[:3]] + [f"{cells[3][0]:+.3f} ± {cells[3][1]:.3f}"]
        lines.append(f"| {travel:g} | {float(rs[0]['funnel_speed_m_per_s']):.4f} | {len(rs)} | " + " | ".join(text) + " |")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    paper_tables.replace_between_markers(DOC, "studies/funnel_scan/run.py --table", text)


def figure():
    """docs/studies/funnel_scan/angles.png: each flank's mean angle against the funnel's travel,
    with one standard error, beside the paper's 28 and 21 degrees."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    with open(CSV, encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    travels = sorted({float(r["travel_over_R"]) for r in rows})
    fig, ax = plt.subplots(figsize=(6, 4))
    for key, label, colour in (("repose_angle_left_deg", "left flank (trailing)", "tab:blue"),
                               ("repose_angle_right_deg", "right flank (the funnel moves towards it)", "tab:red")):
        stats = [mean_se([float(r[key]) for r in rows if float(r["travel_over_R"]) == t]) for t in travels]
        ax.errorbar(travels, [m for m, _ in stats], yerr=[s for _, s in stats], fmt="o-", color=colour,
                    capsize=3, label=label)
    ax.axhline(28, color="tab:blue", ls=":", lw=1, label="paper, left (3900 grains)")
    ax.axhline(21, color="tab:red", ls=":", lw=1, label="paper, right")
    ax.set_xlabel("funnel travel during the pour / base half-width R of a fixed-funnel pile")
    ax.set_ylabel("repose angle (deg)")
    n = len([r for r in rows if float(r["travel_over_R"]) == travels[0]])
    ax.set_title(f"800-grain piles, {n} seeds per travel, mean ± 1 SE", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = os.path.join(os.path.dirname(CSV), "angles.png")
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-P", "--processes", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "funnel_scan"))
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build", "apps", "pilelab"))
    parser.add_argument("--table", action="store_true", help="print the table from the committed CSV and stop")
    args = parser.parse_args()
    if args.table:
        table()
        figure()
    else:
        run(args)


if __name__ == "__main__":
    main()
