#!/usr/bin/python3
"""Figures of a pilelab run: reads OUT/ (dem.h5, profiles.csv, rve_study.csv, report.json) and
writes OUT/figures/NAME.png, with NAME.pdf and NAME.svg beside each for a paper. Run with Debian's
interpreter: /usr/bin/python3 scripts/figures.py OUT

Positions across the pile are x' = (x - x_apex) / R: from the apex of the pile in its half-width
R, the half-width of the wedge of the pile's height and flank angles (report.json, `dem`:
`apex_x_m` and `plate_force_dip.half_width_m`; for an ensemble the wedge of the members' mean
apex, height and flank angles). Axis orientations are tilts of the major axis from the vertical in (-90, 90] degrees,
counter-clockwise positive (docs/studies/paper.md's convention), so an axis near the vertical
never jumps from 180 to 0.

Every figure is made only when its inputs exist, so the script works after any stage.
"""
import csv
import json
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import pilelab  # noqa: E402
from figures_dir import probe_figures_dir  # noqa: E402  (scripts/, this script's folder)

plt.rcParams.update({"font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 8,
                     "xtick.labelsize": 8, "ytick.labelsize": 8, "axes.grid": False,
                     "pdf.fonttype": 42,  # TrueType in the PDF: text a journal's tools can edit
                     "svg.hashsalt": "pilelab"})  # the same SVG ids on every run
FORMATS = ("png", "pdf", "svg")  # every figure in each, beside one another
PNG_DPI = 160
METADATA = {"png": {"Software": None}, "pdf": {"CreationDate": None, "Producer": None}, "svg": {"Date": None}}
LEGEND_RIGHT = dict(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False)

SOURCE_STYLE = {"dem": dict(color="k", marker="o", ms=2, lw=1.0),
                "elastic": dict(color="tab:blue", lw=1.5),
                "fpa": dict(color="tab:red", lw=1.5),
                "osl": dict(color="tab:purple", lw=1.5),
                "elastic_fit": dict(color="tab:green", lw=1.5, ls="--")}
SOURCE_NAME = {"dem": "DEM", "elastic": "elastic", "fpa": "FPA", "osl": "OSL", "elastic_fit": "elastic, fitted"}


def source_name(src):
    return SOURCE_NAME.get(src, src)


def cannot_write(path, error):
    """A full disk or a read-only folder: the file and the system's reason, exit code 2 (bad
    environment, as the C++ stages report it), no traceback."""
    print(f"figures.py: {path}: cannot write: {error.strerror or error}", file=sys.stderr)
    sys.exit(2)


def prepare_figures_dir(out):
    """OUT/figures made and probed before any figure is drawn (scripts/figures_dir.py)."""
    directory, reason = probe_figures_dir(out)
    if reason:
        print(f"figures.py: {directory}: cannot write: {reason}", file=sys.stderr)
        sys.exit(2)


def save(fig, out, name):
    """NAME.png and the same figure as NAME.pdf and NAME.svg, each written whole under a temporary
    name and renamed (never a half-written figure). The temporary name carries the process id (two
    runs never share one) and ends in the format's extension, from which matplotlib takes the
    format."""
    stem = os.path.splitext(name)[0]
    for ext in FORMATS:
        path = os.path.join(out, "figures", f"{stem}.{ext}")
        tmp = f"{path}.tmp.{os.getpid()}.{ext}"
        try:
            fig.savefig(tmp, dpi=PNG_DPI, bbox_inches="tight", pad_inches=0.03, metadata=METADATA[ext])
            os.replace(tmp, path)
            if fig.get_layout_engine() is not None:  # the layout found once serves every format
                fig.set_layout_engine("none")
        except OSError as e:
            if os.path.exists(tmp):
                os.remove(tmp)
            cannot_write(path, e)
        print("wrote", path)
    plt.close(fig)


def _number(value):
    return float(value) if isinstance(value, (int, float)) and math.isfinite(value) else None


def wedge_half_width(height, left_deg, right_deg):
    """R of a wedge of height h and flank angles a, b: half its base, h (cot a + cot b) / 2 (the
    half-width of report.json's dem.plate_force_dip); None without all three."""
    height, left_deg, right_deg = _number(height), _number(left_deg), _number(right_deg)
    if height is None or left_deg is None or right_deg is None or height <= 0:
        return None
    if not (0 < left_deg < 90 and 0 < right_deg < 90):
        return None
    return 0.5 * height * (1 / math.tan(math.radians(left_deg)) + 1 / math.tan(math.radians(right_deg)))


class Frame:
    """Horizontal positions as x' = (x - x_apex) / R, and heights as y / R where a picture keeps
    its aspect. One pile: the apex and R of the report's `dem` section. An ensemble (the members'
    reports given): the members' mean apex, height and flank angles, and R of that mean wedge (the
    pile the later stages take). Else the meshed wedge, or the ensemble section's means about the
    compared axis; without any of them, metres from x = 0."""

    def __init__(self, report, member_reports=()):
        self.apex, self.half_width = self._find(report, list(member_reports))

    @staticmethod
    def _find(report, member_reports):
        dem = report.get("dem") or {}
        apex = _number(dem.get("apex_x_m"))
        half_width = _number((dem.get("plate_force_dip") or {}).get("half_width_m")) or wedge_half_width(
            dem.get("height_m"), dem.get("repose_angle_left_deg"), dem.get("repose_angle_right_deg"))
        if apex is not None and half_width:
            return apex, half_width
        if member_reports:
            def mean(key):
                values = [_number((r.get("dem") or {}).get(key)) for r in member_reports]
                values = [v for v in values if v is not None]
                return sum(values) / len(values) if values else None

            apex = mean("apex_x_m")
            half_width = wedge_half_width(mean("height_m"), mean("repose_angle_left_deg"),
                                          mean("repose_angle_right_deg"))
            if apex is not None and half_width:
                return apex, half_width
        wedge = (report.get("mesh") or {}).get("wedge") or {}
        half_width = wedge_half_width(wedge.get("height_m"), wedge.get("left_angle_deg"), wedge.get("right_angle_deg"))
        if _number(wedge.get("apex_x_m")) is not None and half_width:
            return float(wedge["apex_x_m"]), half_width
        ensemble = report.get("ensemble") or {}
        stat = lambda key: (ensemble.get(key) or {}).get("mean")  # noqa: E731
        half_width = wedge_half_width(stat("height_m"), stat("repose_angle_left_deg"), stat("repose_angle_right_deg"))
        apex = _number((report.get("compare") or {}).get("apex_x_m"))
        if apex is not None and half_width:
            return apex, half_width
        return 0.0, None

    @property
    def scaled(self):
        return self.half_width is not None

    def x(self, x):
        x = np.asarray(x, dtype=float)
        return (x - self.apex) / self.half_width if self.scaled else x

    def y(self, y):
        y = np.asarray(y, dtype=float)
        return y / self.half_width if self.scaled else y

    @property
    def xlabel(self):
        return "(x - x_apex) / R" if self.scaled else "x [m]"

    @property
    def ylabel(self):
        return "y / R" if self.scaled else "y [m]"

    def points(self, xy):
        """(n, 2) positions [m] to the frame: (x - x_apex) / R, y / R."""
        xy = np.asarray(xy, dtype=float)
        return np.stack([self.x(xy[..., 0]), self.y(xy[..., 1])], axis=-1)


def tilt_from_vertical(orientation_deg):
    """An axis' angle from the horizontal, [0, 180) counter-clockwise (fields.h5), as its tilt
    from the vertical in (-90, 90], counter-clockwise positive: an axis is the same turned by
    180 degrees, so 0 is vertical and +-90 horizontal."""
    t = np.asarray(orientation_deg, dtype=float) - 90.0
    return -(np.mod(90.0 - t, 180.0) - 90.0) + 0.0  # + 0.0: a vertical axis reads 0, not -0


def break_wraps(x, tilt):
    """x and tilt with a NaN between neighbours whose tilts differ by more than 90 degrees: there
    the axis passed the horizontal (+-90 are one axis), and a line joining them would cross the
    whole plot."""
    x, tilt = np.asarray(x, dtype=float), np.asarray(tilt, dtype=float)
    if len(x) < 2:
        return x, tilt
    cut = np.flatnonzero(np.abs(np.diff(tilt)) > 90.0) + 1
    return np.insert(x, cut, np.nan), np.insert(tilt, cut, np.nan)


def read_profiles(out):
    """(source, quantity) -> y/h -> [(x, value, stderr)], from profiles.csv."""
    run = pilelab.load(out)
    return {pair: {h: list(map(tuple, rows.tolist())) for h, rows in run.profiles(*pair).items()}
            for pair in run.profiles()}


PILE_WIDTH_IN = 6.3  # the pile pictures' axes width [in]
PILE_MIN_BOX = 0.2  # their least height over width: a flat pile gets room above it, not a sliver


def _pile_figure(xy):
    """A figure and axes for a pile picture spanning the points xy (in the frame), and the limits
    that keep one scale on both axes with the axes at least PILE_MIN_BOX as high as wide."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    (x0, y0), (x1, y1) = xy.min(axis=0), xy.max(axis=0)
    pad = 0.02 * (x1 - x0)
    x0, x1, y0, y1 = x0 - pad, x1 + pad, y0 - pad, y1 + pad
    y1 = max(y1, y0 + PILE_MIN_BOX * (x1 - x0))
    box = (y1 - y0) / (x1 - x0)
    fig, ax = plt.subplots(figsize=(PILE_WIDTH_IN + 0.9, PILE_WIDTH_IN * box + 0.9))
    return fig, ax, (x0, x1), (y0, y1)


def _pile_axes(ax, frame, xlim, ylim):
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(frame.xlabel)
    ax.set_ylabel(frame.ylabel)


def _nice(value):
    """value rounded down to 1, 2 or 5 times a power of ten."""
    if value <= 0:
        return value
    power = 10.0 ** math.floor(math.log10(value))
    return max(m for m in (1, 2, 5) if m * power <= value * (1 + 1e-9)) * power


def pile_figures(out, report):
    run = pilelab.load(out)
    dem, members = run.dem, run.members
    frame = Frame(report)
    if dem is None and members:  # an ensemble: its first member's pile, in its own frame
        dem = members[0].dem
        frame = Frame(members[0].report) if Frame(members[0].report).scaled else frame
    if dem is None:
        return
    s = dem.snapshot()
    whose = f"snapshot '{s.name}'" + (f", member {members[0].seed}" if members else "")
    pressure = s.grain_pressure()
    outlines = [frame.points(p) for p in s.polygons(16)]
    fig, ax, xlim, ylim = _pile_figure(np.concatenate(outlines))
    pc = PolyCollection(outlines, array=pressure, cmap="viridis", edgecolors="none")
    pc.set_clim(0, np.percentile(pressure, 98))
    ax.add_collection(pc)
    _pile_axes(ax, frame, xlim, ylim)
    ax.set_title(f"grains coloured by their pressure ({whose})")
    # The colour bar as tall as the pile's axes (an equal-aspect pile is much lower than the figure).
    fig.colorbar(pc, cax=ax.inset_axes([1.015, 0.0, 0.018, 1.0]), label="grain pressure [N/m]",
                 extend="max")
    save(fig, out, "pile_pressure.png")

    # Contact network: centre to centre, or centre to the contact point on a wall; line width
    # proportional to the normal force, with reference widths in units of the mean force.
    c = s.contacts
    b_centre = s.position[c.grain_b]
    a_end = np.where((c.grain_a >= 0)[:, None], s.position[np.maximum(c.grain_a, 0)], c.point)
    force = np.asarray(c.normal_force, dtype=float)
    mean_f = max(force.mean() if len(c) else 0.0, 1e-30)
    segments = frame.points(np.stack([a_end, b_centre], axis=1))
    fig, ax, xlim, ylim = _pile_figure(np.concatenate([np.concatenate(outlines), segments.reshape(-1, 2)]))
    # Points of line width per mean normal force: 0.6, or less where the strongest contact would
    # be drawn wider than half a mean grain (a big pile drawn at the same width).
    top = force.max() / mean_f if len(c) else 1.0
    grain_pt = float(frame.y(2 * np.sqrt(s.area() / np.pi).mean())) * PILE_WIDTH_IN * 72 / (xlim[1] - xlim[0])
    width_per_mean = min(0.6, 0.5 * grain_pt / max(top, 1.0))
    ax.add_collection(LineCollection(segments, linewidths=width_per_mean * force / mean_f, colors="k",
                                     capstyle="round"))
    _pile_axes(ax, frame, xlim, ylim)
    ax.set_title(f"contact force network ({whose}; {len(c)} contacts)")
    references = sorted({_nice(r) for r in (1.0, top / 2, top) if r > 0})[-3:] if top > 1.5 else [1.0]
    handles = [Line2D([], [], color="k", lw=width_per_mean * r, solid_capstyle="butt") for r in references]
    labels = [f"{r:g} ⟨F⟩ = {r * mean_f:.3g} N" for r in references]
    ax.legend(handles, labels, title="normal force\n(line width ∝ F)", handlelength=2.5, **LEGEND_RIGHT)
    save(fig, out, "force_network.png")


def _curve(ax, frame, rows, src, label, members=0):
    x, v, e = map(np.array, zip(*sorted(rows)))
    x = frame.x(x)
    st = SOURCE_STYLE.get(src, {})
    if src == "dem" and members > 1:
        ax.plot(x, v, color=st["color"], lw=1.2, label=label)
        ax.fill_between(x, v - e, v + e, color="0.6", alpha=0.5, lw=0, label="one standard error")
    elif src == "dem":
        ax.errorbar(x, v, yerr=e if np.nan_to_num(e).any() else None, label=label, capsize=1.5, elinewidth=0.6, **st)
    else:
        ax.plot(x, v, label=label, **st)


def _in_order(ax, labels):
    """The axes' legend entries (from every axes given) in the order of labels (the sources' order;
    matplotlib lists error bars after lines), then any others."""
    found = {}
    for a in np.atleast_1d(ax).flat:
        for handle, label in zip(*a.get_legend_handles_labels()):
            found.setdefault(label, handle)
    keys = [k for k in labels if k in found] + [k for k in found if k not in labels]
    return [found[k] for k in keys], keys


def _mark_axis(ax, frame, feet=True):
    """Thin guides at the apex and (feet) at the wedge's feet, x' = -1 and 1."""
    if frame.scaled:
        for x in (-1.0, 0.0, 1.0) if feet else (0.0,):
            ax.axvline(x, color="0.75", lw=0.6, ls=":" if x else "-", zorder=0)


def profile_figures(out, data, report, frame):
    sources = sorted({s for s, _ in data}, key=lambda s: (s != "dem", s))
    if not sources:
        return
    members = len(report.get("ensemble", {}).get("members", []))
    # Base pressure: sigma_yy / rho g h at the lowest cut, every source. An ensemble's mean is a
    # line with a band of one standard error (over the members) either side.
    lowest = {src: min(data[(src, "sigma_yy")]) for src in sources if data.get((src, "sigma_yy"))}
    if lowest:
        one_cut = len(set(lowest.values())) == 1
        fig, ax = plt.subplots(figsize=(5.6, 3.2), layout="constrained")
        _mark_axis(ax, frame)
        order = []
        for src, y0 in lowest.items():
            name = (f"DEM, mean of {members} piles" if src == "dem" and members > 1 else source_name(src))
            order.append(name if one_cut else f"{name} (y/h = {y0:g})")
            _curve(ax, frame, data[(src, "sigma_yy")][y0], src, order[-1], members)
        ax.set_xlabel(frame.xlabel)
        ax.set_ylabel(r"$\sigma_{yy} / \rho g h$ (compression > 0)")
        ax.set_title("pressure under the pile" + (f", y/h = {next(iter(lowest.values())):g}" if one_cut else "")
                     + (f" (ensemble of {members})" if members > 1 else ""))
        ax.set_ylim(bottom=min(0.0, ax.get_ylim()[0]))
        ax.legend(*_in_order(ax, order), **LEGEND_RIGHT)
        ax.grid(alpha=0.3)
        save(fig, out, "base_pressure.png")

    # Height profiles: one panel per cut, each over its own width of the pile.
    d = data.get(("dem", "sigma_yy")) or next(iter(data.values()))
    heights = sorted(d)
    ncols = len(heights) if len(heights) <= 4 else math.ceil(len(heights) / 2)
    nrows = math.ceil(len(heights) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(min(7.0, 1.9 * ncols + 0.6), 2.3 * nrows),
                             sharey=True, squeeze=False, layout="constrained")
    for k, ax in enumerate(axes.flat):
        if k >= len(heights):
            ax.set_visible(False)
            continue
        h = heights[k]
        _mark_axis(ax, frame, feet=False)
        for src in sources:
            dd = data.get((src, "sigma_yy"), {}).get(h)
            if dd:
                _curve(ax, frame, dd, src, source_name(src) + (" (mean)" if src == "dem" and members > 1 else ""),
                       members)
        ax.set_title(f"y/h = {h:g}")
        ax.grid(alpha=0.3)
        if k % ncols == 0:
            ax.set_ylabel(r"$\sigma_{yy} / \rho g h$")
        ax.set_xlabel(frame.xlabel)
    names = [source_name(src) + (" (mean)" if src == "dem" and members > 1 else "") for src in sources]
    fig.legend(*_in_order(axes, names), loc="upper left", bbox_to_anchor=(1.0, 0.95), frameon=False)
    save(fig, out, "sigma_yy_profiles.png")

    # Orientations of stress, strain and fabric (the paper's Fig. 15) at the two lowest cuts: the
    # major axis' tilt from the vertical.
    cuts = heights[:2]
    fig, axes = plt.subplots(1, len(cuts), figsize=(3.1 * len(cuts) + 0.4, 2.9), sharey=True, squeeze=False,
                             layout="constrained")
    model_sources = sorted({src for src, q in data if src != "dem" and q == "stress_orientation_deg"})
    for ax, h in zip(axes[0], cuts):
        _mark_axis(ax, frame)
        ax.axhline(0, color="0.6", lw=0.6, zorder=0)
        for q, c, name in (("stress_orientation_deg", "tab:red", "DEM stress"),
                           ("strain_orientation_deg", "tab:blue", "DEM strain"),
                           ("fabric_orientation_deg", "tab:green", "DEM fabric")):
            dd = data.get(("dem", q), {}).get(h)
            if dd:
                x, v, _ = map(np.array, zip(*sorted(dd)))
                ax.plot(*break_wraps(frame.x(x), tilt_from_vertical(v)), color=c, lw=1.2, label=name)
        for src, ls in zip(model_sources, ("--", ":", "-.", (0, (1, 3)))):
            dd = data.get((src, "stress_orientation_deg"), {}).get(h)
            if dd:
                x, v, _ = map(np.array, zip(*sorted(dd)))
                ax.plot(*break_wraps(frame.x(x), tilt_from_vertical(v)), color="k", ls=ls, lw=1.2,
                        label=f"{source_name(src)} stress")
        ax.set_title(f"y/h = {h:g}")
        ax.set_xlabel(frame.xlabel)
        ax.set_ylim(-90, 90)
        ax.set_yticks(np.arange(-90, 91, 30))
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("major axis' tilt from the vertical [deg]\n(counter-clockwise > 0)")
    fig.legend(*_in_order(axes, []), loc="upper left", bbox_to_anchor=(1.0, 0.95), frameon=False)
    save(fig, out, "orientations.png")


RVE_PANELS = (("stress_xx", r"$\sigma_{xx}$ [N/m]"), ("stress_yy", r"$\sigma_{yy}$ [N/m]"),
              ("stress_xy", r"$\sigma_{xy}$ [N/m]"), ("fabric_xx", r"$F_{xx}$"), ("fabric_yy", r"$F_{yy}$"),
              ("fabric_xy", r"$F_{xy}$"), ("strain_xx", r"$\varepsilon_{xx}$"), ("strain_yy", r"$\varepsilon_{yy}$"),
              ("strain_xy", r"$\varepsilon_{xy}$"), ("volume_fraction", "volume fraction"),
              ("coordination", "coordination number"))


def rve_figure(out, report, frame):
    """The RVE-size study (the paper's Figs. 5-6): one panel per quantity against the grains in
    the RVE (log scale, shared), a line per study point, the chosen size marked."""
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
    known = [q for q, _ in RVE_PANELS]
    panels = [(q, label) for q, label in RVE_PANELS if any((p, q) in series for p in points)]
    panels += [(q, q) for q in sorted({q for _, q in series} - set(known))]
    if not panels:
        return
    coarse = report.get("coarse") or {}
    study = coarse.get("rve_study") or {}
    chosen = _number(study.get("chosen_grain_count"))
    used = _number(coarse.get("rve_grain_count_target")) if coarse.get("method") == "rve" else None
    height = _number((report.get("compare") or {}).get("height_m")) or _number(coarse.get("height_m"))

    def point_label(p):
        x, y = where[p]
        xs = f"x' = {float(frame.x(x)):+.2f}" if frame.scaled else f"x = {x:.3f} m"
        return xs + (f", y/h = {y / height:.2f}" if height else f", y = {y:.3f} m")

    ncols = 3
    nrows = math.ceil((len(panels) + 1) / ncols)  # one slot for the legend
    fig, axes = plt.subplots(nrows, ncols, figsize=(7.0, 1.75 * nrows + 0.3), sharex=True, squeeze=False,
                             layout="constrained")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, ax in enumerate(axes.flat):
        if k >= len(panels):
            ax.axis("off")
            continue
        q, label = panels[k]
        for i, p in enumerate(points):
            s = sorted(series.get((p, q), []))
            if s:
                n, v = zip(*s)
                ax.plot(n, v, marker=".", ms=3, lw=1.0, color=colors[i % len(colors)], label=point_label(p))
        if chosen:
            ax.axvline(chosen, color="k", ls="--", lw=0.9, label=f"chosen: {chosen:g} grains")
        if used and used != chosen:
            ax.axvline(used, color="0.4", ls=":", lw=0.9, label=f"the fields' RVE: {used:g} grains")
        ax.set_xscale("log")
        ax.set_ylabel(label)
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useMathText=True)
        ax.grid(alpha=0.3)
        if k + ncols >= len(panels):
            ax.set_xlabel("grains in the RVE")
            ax.xaxis.set_tick_params(labelbottom=True)
    counts = [n for (_, q), s in series.items() for n, _ in s if n > 0]
    if counts:  # grain counts as plain numbers; 1-2-5 steps where the study spans under two decades
        subs = (1.0, 2.0, 5.0) if max(counts) < 100 * min(counts) else (1.0,)
        axes.flat[0].xaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=subs))
        axes.flat[0].xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        axes.flat[0].xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    handles, labels = _in_order(axes.flat[:len(panels)], [])
    spare = axes.flat[len(panels)] if len(panels) < axes.size else None
    title = f"study points (tolerance {study['tolerance']:g})" if _number(study.get("tolerance")) else "study points"
    if spare is not None:
        spare.legend(handles, labels, loc="center", frameon=False, title=title)
    else:
        fig.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.0, 0.95), frameon=False, title=title)
    fig.suptitle("RVE size study: averages against the grains in the RVE (stress tension > 0)", fontsize=9)
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
    values = [float(r[k]) for r in rows for k in ["measured_N_per_m"] + [m + "_N_per_m" for m in models]]
    lo, hi = min(values), max(values)
    pad = 0.05 * (hi - lo or 1.0)
    fig, axes = plt.subplots(1, len(models), figsize=(min(7.0, 2.3 * len(models) + 0.8), 2.6), squeeze=False,
                             sharex=True, sharey=True, layout="constrained")
    fits = report.get("fit", {}).get("models", {})
    for ax, m in zip(axes[0], models):
        ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], color="0.5", lw=0.8, zorder=0, label="fitted = DEM")
        for comp, c in (("xx", "tab:blue"), ("yy", "tab:red"), ("xy", "tab:green")):
            pts = [(float(r["measured_N_per_m"]), float(r[m + "_N_per_m"])) for r in rows if r["component"] == comp]
            if pts:
                x, y = zip(*pts)
                ax.scatter(x, y, s=6, color=c, label=r"$\Delta\sigma_{%s}$" % comp)
        info = fits.get(m, {})
        r2, aic = _number(info.get("r2")), _number(info.get("aic"))
        ax.set_title(m.replace("_", " ") + "\n" + (f"R$^2$ = {r2:.2f}" if r2 is not None else "R$^2$ n/a")
                     + (f", AIC = {aic:.0f}" if aic is not None else ""))
        ax.set_xlim(lo - pad, hi + pad)
        ax.set_ylim(lo - pad, hi + pad)
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("DEM stress change [N/m]")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("fitted model [N/m]")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.0, 0.9), frameon=False)
    save(fig, out, "fit_scatter.png")


def ensemble_figure(out, report):
    """The members' flank angles, each member a point, with the ensemble mean and its one
    standard error band per flank."""
    e = report.get("ensemble")
    if not e or not e.get("members"):
        return
    seeds = [m["seed"] for m in e["members"]]
    k = np.arange(len(seeds))
    fig, ax = plt.subplots(figsize=(max(3.6, 0.35 * len(seeds) + 2.0), 2.8), layout="constrained")
    for side, color, dx in (("left", "tab:blue", -0.1), ("right", "tab:red", 0.1)):
        angle = np.array([m.get(f"repose_angle_{side}_deg") if m.get(f"repose_angle_{side}_deg") is not None
                          else np.nan for m in e["members"]], dtype=float)
        stat = e.get(f"repose_angle_{side}_deg", {})
        label = f"{side} flank"
        if stat.get("mean") is not None:
            mean, se = stat["mean"], stat.get("standard_error") or 0.0
            ax.axhline(mean, color=color, lw=1)
            ax.axhspan(mean - se, mean + se, color=color, alpha=0.15, lw=0)
            label += f": {mean:.1f} ± {se:.1f}°"
        ax.plot(k + dx, angle, "o", ms=4, color=color, label=label)
    ax.set_xticks(k)
    ax.set_xticklabels([str(s) for s in seeds])
    ax.set_xlim(-0.6, len(seeds) - 0.4)
    ax.set_xlabel("member (seed)")
    ax.set_ylabel("repose angle [deg]")
    ax.set_title(f"flank angles of {len(seeds)} piles\n(lines: means, bands: one standard error)")
    ax.grid(alpha=0.3)
    ax.legend(**LEGEND_RIGHT)
    save(fig, out, "ensemble_angles.png")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: /usr/bin/python3 scripts/figures.py OUT")
    out = sys.argv[1]
    prepare_figures_dir(out)
    report_path = os.path.join(out, "report.json")
    report = json.load(open(report_path)) if os.path.exists(report_path) else {}
    frame = Frame(report, [m.report for m in pilelab.load(out).members])
    pile_figures(out, report)
    profile_figures(out, read_profiles(out), report, frame)
    ensemble_figure(out, report)
    rve_figure(out, report, frame)
    fit_figure(out, report)


if __name__ == "__main__":
    main()
