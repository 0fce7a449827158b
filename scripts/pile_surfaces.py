#!/usr/bin/python3
"""Several DEM piles side by side: their settled surfaces, apex at x = 0, in one figure, and a
table of their repose angles with the mean and standard error over all flanks.

    /usr/bin/python3 scripts/pile_surfaces.py FIGURE.png OUT1 OUT2 ...

Each OUT is the output directory of `pilelab dem` (dem.h5 and report.json). The angles are the
run's own (report.json: the surface fit of docs/DEM.md); the figure draws the highest grain
centre in bins two mean diameters wide, the same bins the fit uses.
"""
import json
import os
import sys
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def surface(positions, bin_width):
    """Highest grain centre per bin of the x range, as (bin centres, heights)."""
    x, y = positions[:, 0], positions[:, 1]
    bins = np.floor((x - x.min()) / bin_width).astype(int)
    top = np.full(bins.max() + 1, -np.inf)
    np.maximum.at(top, bins, y)
    filled = np.isfinite(top)
    centres = x.min() + (np.arange(top.size) + 0.5) * bin_width
    return centres[filled], top[filled]


def angle_text(angle, width=0):
    """An angle with one decimal, or n/a when the run could not fit that flank (null in report.json)."""
    return f"{'n/a' if angle is None else f'{angle:.1f}':>{width}s}"


def main(figure, runs):
    fig, ax = plt.subplots(figsize=(10, 3.6))
    flanks, highest = [], 0.0
    print(f"{'run':40s} {'seed':>6s} {'integrator':>10s} {'dt [s]':>9s} {'height [m]':>10s} {'left':>6s} {'right':>6s}")
    for out in runs:
        with h5py.File(os.path.join(out, "dem.h5"), "r") as f:
            positions = f["snapshots/settled/position"][:]
            run = dict(f["run"].attrs)
            scene = tomllib.loads(f["scene"][()].decode())
        report = json.load(open(os.path.join(out, "report.json")))["dem"]
        left, right = report["repose_angle_left_deg"], report["repose_angle_right_deg"]
        flanks += [a for a in (left, right) if a is not None]
        seed = int(run.get("seed", -1))
        integrator = run.get("integrator", b"?")
        integrator = integrator.decode() if isinstance(integrator, bytes) else str(integrator)
        dt = float(run.get("time_step_s", np.nan))
        mean_diameter = scene.get("dem", {}).get("grains", {}).get("mean_diameter_m", 6.8e-3)  # docs/SCENES.md default
        xs, ys = surface(positions, 2.0 * mean_diameter)
        xs = xs - report.get("apex_x_m", xs[np.argmax(ys)])
        highest = max(highest, ys.max())
        ax.plot(xs, ys, lw=1, label=f"seed {seed}, {integrator} {dt:.3g} s: {angle_text(left)} / {angle_text(right)} deg")
        print(f"{out:40s} {seed:6d} {integrator:>10s} {dt:9.3g} {report['height_m']:10.3f} {angle_text(left, 6)} {angle_text(right, 6)}")
    if flanks:
        mean, spread = np.mean(flanks), np.std(flanks, ddof=1) if len(flanks) > 1 else np.nan
        print(f"{len(flanks)} flanks: mean {mean:.1f} deg, standard deviation {spread:.1f}, "
              f"standard error of the mean {spread / np.sqrt(len(flanks)):.1f}")
    ax.set_aspect("equal")
    ax.set_ylim(0, 1.7 * highest)  # room for the legend above the piles
    ax.set_xlabel(r"$x - x_{apex}$ [m]")
    ax.set_ylabel("highest grain centre [m]")
    ax.set_title("settled surfaces; repose angles left / right from each run's report", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", ncol=2)
    fig.tight_layout()
    tmp = figure + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, figure)  # never leave a half-written figure in place


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
