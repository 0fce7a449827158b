#!/usr/bin/python3
"""Figures of a pilelab run: reads OUT/ (dem.h5, profiles.csv, rve_study.csv, report.json) and
writes OUT/figures/*.png. Run with Debian's interpreter: /usr/bin/python3 scripts/figures.py OUT

Every figure is made only when its inputs exist, so the script works after any stage.
"""
import csv
import json
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import pilelab  # noqa: E402

SOURCE_STYLE = {"dem": dict(color="k", marker="o", ms=3, lw=1.2),
                "elastic": dict(color="tab:blue", lw=1.8),
                "fpa": dict(color="tab:red", lw=1.8),
                "osl": dict(color="tab:purple", lw=1.8),
                "elastic_fit": dict(color="tab:green", lw=1.8, ls="--")}
LABEL = {"sigma_yy": r"$\sigma_{yy}/\rho g h$", "sigma_xx": r"$\sigma_{xx}/\rho g h$",
         "sigma_xy": r"$\sigma_{xy}/\rho g h$", "stress_orientation_deg": "major stress axis [deg]",
         "strain_orientation_deg": "major strain axis [deg]", "fabric_orientation_deg": "major fabric axis [deg]"}


def cannot_write(path, error):
    """A full disk or a read-only folder: the file and the system's reason, exit code 2 (bad
    environment, as the C++ stages report it), no traceback."""
    print(f"figures.py: {path}: cannot write: {error.strerror or error}", file=sys.stderr)
    sys.exit(2)


def prepare_figures_dir(out):
    """OUT/figures made and probed before any figure is drawn, as the stages probe their folders."""
    directory = os.path.join(out, "figures")
    probe = os.path.join(directory, f".probe.tmp.{os.getpid()}")
    try:
        os.makedirs(directory, exist_ok=True)
        with open(probe, "wb") as f:
            f.write(b"\0" * 4096)
            f.flush()
            os.fsync(f.fileno())
        os.remove(probe)
    except OSError as e:
        if os.path.exists(probe):
            os.remove(probe)
        cannot_write(directory, e)


def save(fig, out, name):
    path = os.path.join(out, "figures", name)
    tmp = path + f".tmp.{os.getpid()}.png"  # a process's own: two runs never share one
    try:
        fig.savefig(tmp, dpi=130, bbox_inches="tight")
        os.replace(tmp, path)  # never a half-written figure
    except OSError as e:
        if os.path.exists(tmp):
            os.remove(tmp)
        cannot_write(path, e)
    plt.close(fig)
    print("wrote", path)


def read_profiles(out):
    """(source, quantity) -> y/h -> [(x, value, stderr)], from profiles.csv."""
    run = pilelab.load(out)
    return {pair: {h: list(map(tuple, rows.tolist())) for h, rows in run.profiles(*pair).items()}
            for pair in run.profiles()}


def pile_figures(out, report):
    run = pilelab.load(out)
    dem, members = run.dem, run.members
    if dem is None and members:  # an ensemble: its first member's pile
        dem = members[0].dem
    if dem is None:
        return
    s = dem.snapshot()
    pressure = s.grain_pressure()
    fig, ax = plt.subplots(figsize=(11, 4.2))
    pc = PolyCollection(s.polygons(16), array=pressure, cmap="viridis", edgecolors="none")
    pc.set_clim(0, np.percentile(pressure, 98))
    ax.add_collection(pc)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"grains coloured by pressure (snapshot '{s.name}'" + (f", member {members[0].seed})" if members else ")"))
    fig.colorbar(pc, ax=ax, label="grain pressure [N/m]", shrink=0.8)
    save(fig, out, "pile_pressure.png")

    # Contact network: centre to centre, or centre to the contact point on a wall.
    c = s.contacts
    b_centre = s.position[c.grain_b]
    a_end = np.where((c.grain_a >= 0)[:, None], s.position[np.maximum(c.grain_a, 0)], c.point)
    mean_f = max(c.normal_force.mean() if len(c) else 0.0, 1e-30)
    fig, ax = plt.subplots(figsize=(11, 4.2))
    ax.add_collection(LineCollection(np.stack([a_end, b_centre], axis=1), linewidths=0.4 * c.normal_force / mean_f,
                                     colors="k"))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"contact force network (line width ~ normal force; mean {mean_f:.3g} N)")
    save(fig, out, "force_network.png")


def profile_figures(out, data, report):
    sources = sorted({s for s, _ in data})
    if not sources:
        return
    members = len(report.get("ensemble", {}).get("members", []))
    # Base pressure: sigma_yy / rho g h at the lowest cut, every source. An ensemble's mean is a
    # line with a band of one standard error (over the members) either side.
    fig, ax = plt.subplots(figsize=(7, 4))
    for src in sources:
        d = data.get((src, "sigma_yy"))
        if not d:
            continue
        y0 = min(d)
        x, v, e = map(np.array, zip(*sorted(d[y0])))
        st = SOURCE_STYLE.get(src, {})
        if src == "dem" and members > 1:
            ax.plot(x, v, color=st["color"], lw=1.4, label=f"dem, mean of {members} piles (y/h = {y0:g})")
            ax.fill_between(x, v - e, v + e, color="0.6", alpha=0.5, lw=0, label="one standard error")
        elif src == "dem":
            ax.errorbar(x, v, yerr=e if e.any() else None, label=f"{src} (y/h = {y0:g})", capsize=2, **st)
        else:
            ax.plot(x, v, label=f"{src} (y/h = {y0:g})", **st)
    ax.set_xlabel("x [m]")
    ax.set_ylabel(r"$\sigma_{yy} / \rho g h$ (compression > 0)")
    ax.set_title("pressure under the pile" + (f" (ensemble of {members})" if members > 1 else ""))
    ax.legend()
    ax.grid(alpha=0.3)
    save(fig, out, "base_pressure.png")

    # Height profiles: one panel per cut.
    d = data.get(("dem", "sigma_yy")) or next(iter(data.values()))
    heights = sorted(d)
    fig, axes = plt.subplots(1, len(heights), figsize=(3.4 * len(heights), 3.4), sharey=True, squeeze=False)
    for ax, h in zip(axes[0], heights):
        for src in sources:
            dd = data.get((src, "sigma_yy"), {}).get(h)
            if not dd:
                continue
            x, v, e = map(np.array, zip(*sorted(dd)))
            st = SOURCE_STYLE.get(src, {})
            if src == "dem":
                ax.errorbar(x, v, yerr=e if e.any() else None, label=src, capsize=2, **st)
            else:
                ax.plot(x, v, label=src, **st)
        ax.set_title(f"y/h = {h:g}")
        ax.set_xlabel("x [m]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel(r"$\sigma_{yy} / \rho g h$")
    axes[0][0].legend()
    save(fig, out, "sigma_yy_profiles.png")

    # Orientations of stress, strain and fabric (the paper's Fig. 15) at the two lowest cuts.
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, h in zip(axes, heights[:2]):
        for q, c in (("stress_orientation_deg", "tab:red"), ("strain_orientation_deg", "tab:blue"),
                     ("fabric_orientation_deg", "tab:green")):
            dd = data.get(("dem", q), {}).get(h)
            if dd:
                x, v, _ = map(np.array, zip(*sorted(dd)))
                ax.plot(x, v, color=c, label=q.split("_")[0])
        model_sources = sorted({src for src, q in data if src != "dem" and q == "stress_orientation_deg"})
        for src, st in zip(model_sources, ("--", ":", "-.", (0, (1, 3)))):
            dd = data.get((src, "stress_orientation_deg"), {}).get(h)
            if dd:
                x, v, _ = map(np.array, zip(*sorted(dd)))
                ax.plot(x, v, color="k", ls=st, label=f"{src} stress")
        ax.axhline(90, color="0.7", lw=0.8)
        ax.set_title(f"y/h = {h:g}")
        ax.set_xlabel("x [m]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("major axis from the horizontal [deg] (90 = vertical)")
    axes[0].legend()
    save(fig, out, "orientations.png")


def rve_figure(out):
    path = os.path.join(out, "rve_study.csv")
    if not os.path.exists(path):
        return
    series = defaultdict(list)
    where = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            series[(int(r["point"]), r["quantity"])].append((int(r["grain_count"]), float(r["value"])))
            where[int(r["point"])] = (float(r["x_m"]), float(r["y_m"]))
    points = sorted({p for p, _ in series})
    groups = [("stress [N/m]", ["stress_xx", "stress_yy", "stress_xy"]), ("fabric", ["fabric_xx", "fabric_yy", "fabric_xy"]),
              ("strain", ["strain_xx", "strain_yy", "strain_xy"]), ("scalars", ["volume_fraction", "coordination"])]
    fig, axes = plt.subplots(len(points), len(groups), figsize=(4 * len(groups), 3.2 * len(points)), squeeze=False,
                             layout="constrained")
    for i, p in enumerate(points):
        for j, (title, qs) in enumerate(groups):
            ax = axes[i][j]
            for q in qs:
                s = series.get((p, q))
                if s:
                    n, v = zip(*s)
                    ax.plot(n, v, marker=".", label=q)
            ax.set_xscale("log")
            ax.set_xlabel("grains in the RVE")
            ax.set_title(f"({where[p][0]:.3f} m, {where[p][1]:.3f} m): {title}", fontsize=9)
            ax.legend(fontsize=7)
            ax.grid(alpha=0.3)
    save(fig, out, "rve_convergence.png")


def fit_figure(out, report):
    path = os.path.join(out, "fit_samples.csv")
    if not os.path.exists(path):
        return
    with open(path) as f:
        rows = list(csv.DictReader(f))
    models = [k[:-len("_N_per_m")] for k in rows[0] if k.endswith("_N_per_m") and k != "measured_N_per_m"] if rows else []
    if not models:
        return
    fig, axes = plt.subplots(1, len(models), figsize=(4.2 * len(models), 4), squeeze=False, layout="constrained")
    fits = report.get("fit", {}).get("models", {})
    for ax, m in zip(axes[0], models):
        for comp, c in (("xx", "tab:blue"), ("yy", "tab:red"), ("xy", "tab:green")):
            pts = [(float(r["measured_N_per_m"]), float(r[m + "_N_per_m"])) for r in rows if r["component"] == comp]
            if pts:
                x, y = zip(*pts)
                ax.scatter(x, y, s=8, color=c, label=r"$\Delta\sigma_{%s}$" % comp)
        lo = min(float(r["measured_N_per_m"]) for r in rows)
        hi = max(float(r["measured_N_per_m"]) for r in rows)
        ax.plot([lo, hi], [lo, hi], color="0.5", lw=0.8)
        info = fits.get(m, {})
        ax.set_title(f"{m}: R$^2$ = {info.get('r2', float('nan')):.2f}, AIC = {info.get('aic', float('nan')):.0f}", fontsize=9)
        ax.set_xlabel("DEM stress change [N/m]")
        ax.set_ylabel("fitted model [N/m]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, out, "fit_scatter.png")


def ensemble_figure(out, report):
    """The members' flank angles, each member a point, with the ensemble mean and its one
    standard error band per flank."""
    e = report.get("ensemble")
    if not e or not e.get("members"):
        return
    seeds = [m["seed"] for m in e["members"]]
    k = np.arange(len(seeds))
    fig, ax = plt.subplots(figsize=(max(5, 0.45 * len(seeds) + 2), 3.6))
    for side, color, dx in (("left", "tab:blue", -0.1), ("right", "tab:red", 0.1)):
        angle = np.array([m.get(f"repose_angle_{side}_deg") if m.get(f"repose_angle_{side}_deg") is not None
                          else np.nan for m in e["members"]], dtype=float)
        ax.plot(k + dx, angle, "o", color=color, label=f"{side} flank")
        stat = e.get(f"repose_angle_{side}_deg", {})
        if stat.get("mean") is not None:
            mean, se = stat["mean"], stat.get("standard_error") or 0.0
            ax.axhline(mean, color=color, lw=1)
            ax.axhspan(mean - se, mean + se, color=color, alpha=0.15, lw=0)
            ax.text(len(seeds) - 0.5, mean, f" {mean:.1f} ± {se:.1f}", color=color, va="center")
    ax.set_xticks(k)
    ax.set_xticklabels([str(s) for s in seeds])
    ax.set_xlabel("member (seed)")
    ax.set_ylabel("repose angle [deg]")
    ax.set_title(f"flank angles of {len(seeds)} piles: mean and one standard error")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, out, "ensemble_angles.png")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: /usr/bin/python3 scripts/figures.py OUT")
    out = sys.argv[1]
    prepare_figures_dir(out)
    report_path = os.path.join(out, "report.json")
    report = json.load(open(report_path)) if os.path.exists(report_path) else {}
    pile_figures(out, report)
    profile_figures(out, read_profiles(out), report)
    ensemble_figure(out, report)
    rve_figure(out)
    fit_figure(out, report)


if __name__ == "__main__":
    main()
