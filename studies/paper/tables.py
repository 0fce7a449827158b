#!/usr/bin/python3
"""The paper study's table and figures, from the committed products alone (no pouring, no
pilelab binary): docs/studies/paper.md's table between its markers, and the PNGs in
docs/studies/paper/.

    /usr/bin/python3 studies/paper/tables.py [STUDY_DIR] [--doc docs/studies/paper.md]

STUDY_DIR (docs/studies/paper/symmetric) holds products/ from studies/paper/stages.py:
fields.h5 with every pile's own fields (/piles/K), report.json, profiles.csv.gz.

Every number of the table is a statistic of the ensemble mean fields, and its standard error is
the jackknife over piles: the statistic recomputed with each pile left out (the mean fields
re-averaged over the others), SE^2 = (n - 1)/n * sum (s_k - s_mean)^2. Regions are given in
x' = (x - x_apex) / R (R the base half-width on that side) and y / h: the core is |x'| < 0.15,
0.05 < y/h < 0.35; the flanks 0.4 < |x'| < 0.7 at the same heights; the surface layer the points
less than 0.1 h below the wedge's flank (y/h > 1 - |x'| - 0.1); the outer layer one to two RVE
radii below it (for the density: nearer the flank, a member's own surface stands above or below
the mean wedge and grain area over RVE-in-mesh area is no volume fraction).
"""
import argparse
import contextlib
import csv
import gzip
import json
import os
import re
import sys
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "python"))
import pilelab  # noqa: E402


class Ensemble:
    """Each pile's fields at the mesh points, and statistics of their mean with jackknife errors."""

    def __init__(self, products):
        fields = pilelab.Fields(os.path.join(products, "fields.h5"))
        self.attrs, self.points, nodes, self.piles = fields.attrs, fields.points, fields.nodes, fields.piles
        with open(os.path.join(products, "report.json"), encoding="utf-8") as f:
            self.report = json.load(f)
        self.n = len(self.piles)
        self.h = float(self.attrs["height_m"])
        self.apex = float(self.report["compare"]["apex_x_m"])
        base = nodes[nodes[:, 1] < 1e-9 * self.h + 1e-12]
        left, right = self.apex - base[:, 0].min(), base[:, 0].max() - self.apex
        x = self.points[:, 0] - self.apex
        self.xr = np.where(x < 0, x / left, x / right)  # x' in [-1, 1]
        self.yh = self.points[:, 1] / self.h
        self.R = 0.5 * (left + right)

    # Regions of the pile (masks over the points).
    def core(self):
        return (np.abs(self.xr) < 0.15) & (self.yh > 0.05) & (self.yh < 0.35)

    def flanks(self, side=0):
        m = (np.abs(self.xr) > 0.4) & (np.abs(self.xr) < 0.7) & (self.yh > 0.05) & (self.yh < 0.35)
        return m & (np.sign(self.xr) == side) if side else m

    def surface_layer(self):
        return (self.yh > 1 - np.abs(self.xr) - 0.1) & (np.abs(self.xr) > 0.15)

    def outer_layer(self):
        """One to two RVE radii below the wedge's flank: the outermost points whose RVE lies
        inside every member (nearer the surface, the members' own flanks stand above or below
        the mean wedge, and grain area over RVE-in-mesh area is no volume fraction)."""
        depth = (1 - np.abs(self.xr) - self.yh) * self.h  # vertical, below the wedge's flank
        r = float(self.attrs["rve_radius_m"])
        return (depth > r) & (depth < 2 * r) & (np.abs(self.xr) > 0.15)

    def interior(self):
        """At least one RVE radius below the wedge's flank (see outer_layer)."""
        return (1 - np.abs(self.xr) - self.yh) * self.h > float(self.attrs["rve_radius_m"])

    def band(self, y_over_h, half=0.03):
        return np.abs(self.yh - y_over_h) < half

    def mean_fields(self, piles):
        """Q -> the mean over the given piles (NaN where none has data); computed once per set
        of piles (every row's jackknife uses the same n + 1 sets)."""
        key = tuple(piles)
        cache = self.__dict__.setdefault("_means", {})
        if key not in cache:
            stack = lambda q: np.array([self.piles[k][q] for k in piles])  # noqa: E731
            with _quiet():
                cache[key] = {q: np.nanmean(stack(q), axis=0) for q in self.piles[piles[0]]}
        return cache[key]

    def statistic(self, function):
        """function(Fields) -> float or tuple of floats; returns (value, stderr) arrays."""
        keys = sorted(self.piles)
        full = np.atleast_1d(np.asarray(function(Fields(self, self.mean_fields(keys))), dtype=float))
        if self.n < 2:
            return full, np.full_like(full, np.nan)
        leave_out = np.array([np.atleast_1d(function(Fields(self, self.mean_fields([j for j in keys if j != k]))))
                              for k in keys], dtype=float)
        se = np.sqrt((self.n - 1) / self.n * np.sum((leave_out - leave_out.mean(axis=0)) ** 2, axis=0))
        return full, se


@contextlib.contextmanager
def _quiet():
    """Means of empty selections are NaN by design here: no RuntimeWarning for them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


class Fields:
    """Mean fields of a set of piles, with the derived quantities of docs/FORMAT.md."""

    def __init__(self, ensemble, values):
        self.e, self.v = ensemble, values

    def __getitem__(self, q):
        return self.v[q]

    def axes(self, kind):
        """Principal axes of the mean tensor: (anisotropy, tilt of the major axis from the
        vertical in degrees, counter-clockwise positive). Stress: compression positive;
        strain: the eigenvalue of largest magnitude is the major one (as coarse/ defines them);
        fabric: positive definite, so its anisotropy is the deviatoric fraction radius / mean."""
        sign = -1.0 if kind == "stress" else 1.0
        xx, yy, xy = (sign * self.v[f"{kind}_{c}"] for c in ("xx", "yy", "xy"))
        mean, radius = 0.5 * (xx + yy), np.hypot(0.5 * (xx - yy), xy)
        major, minor = mean + radius, mean - radius
        theta = 0.5 * np.degrees(np.arctan2(2 * xy, xx - yy))  # the larger eigenvalue's axis
        if kind == "strain":
            swap = np.abs(minor) > np.abs(major)
            theta = np.where(swap, theta + 90.0, theta)
        size = np.abs(major) + np.abs(minor)
        anisotropy = (major - minor) / np.where(size > 0, size, np.nan)
        tilt = (theta - 90.0 + 90.0) % 180.0 - 90.0  # the major axis from the vertical, in (-90, 90]
        return anisotropy, tilt

    def mean(self, q, mask):
        with _quiet():
            return float(np.nanmean(np.asarray(q)[mask]))

    def profile(self, q, y_over_h, bins=np.linspace(-1, 1, 41)):
        """Bin means of q along the band at y/h (x' bins of 0.05): centres, values."""
        m = self.e.band(y_over_h)
        idx = np.digitize(self.e.xr[m], bins) - 1
        values = np.asarray(q)[m]
        out = np.full(len(bins) - 1, np.nan)
        with _quiet():
            for b in range(len(bins) - 1):
                sel = (idx == b) & np.isfinite(values)
                if sel.sum() >= 2:
                    out[b] = values[sel].mean()
        return 0.5 * (bins[1:] + bins[:-1]), out


def angle_between_axes(t1, t2):
    d = np.abs(t1 - t2) % 180.0
    return np.minimum(d, 180.0 - d)


def fmt(value, se, digits=2):
    if not np.isfinite(value):
        return "n/a"
    if not np.isfinite(se):
        return f"{value:.{digits}f}"
    return f"{value:.{digits}f} ± {se:.{digits}f}"


def findings(e):
    """The table's rows: (finding, paper, ours, verdict)."""
    rows = []
    ens = e.report["ensemble"]

    def stat(function):
        v, s = e.statistic(function)
        return v, s

    def row(finding, paper, value, se, verdict_fn, digits=2, note=""):
        ours = fmt(value, se, digits)
        rows.append((finding, paper, ours, verdict_fn(value, se) + (f"; {note}" if note else "")))

    def near(target, tol=0.0):
        # Agrees when the paper's value (which carries no error) lies within 2 SE (+ the paper's
        # own reading tolerance) of ours.
        return lambda v, s: "agrees within errors" if abs(v - target) <= 2 * s + tol else (
            "differs" + (f" ({(v - target) / s:+.1f} SE)" if s > 0 else ""))

    def sign(expected_positive):
        return lambda v, s: ("agrees (beyond 2 SE)" if (v > 2 * s if expected_positive else v < -2 * s)
                             else "within 2 SE of none: not resolved" if abs(v) <= 2 * s else "opposite sign")

    # Repose angles.
    for side, name in (("left", "left"), ("right", "right"), ("pile_mean", "mean of both flanks")):
        s = ens[f"repose_angle_{side}_deg"]
        row(f"repose angle, {name} (deg)", "about 28", s["mean"], s["standard_error"], near(28.0, 0.5), 1,
            "SE over the piles' own angles")

    # Density (Fig. 7).
    v, s = stat(lambda F: F.mean(F["volume_fraction"], e.core()) / F.mean(F["volume_fraction"], e.outer_layer()) - 1)
    row("density: core over the outer layer (1-2 RVE radii deep), minus 1", "0.08-0.10", v[0], s[0], near(0.09, 0.01), 3)

    def x_of_extreme(q, y, find_max=True):
        def f(F):
            x, p = F.profile(F[q] if isinstance(q, str) else q(F), y)
            inner = np.abs(x) < 0.8
            p = np.where(inner & np.isfinite(p), p, -np.inf if find_max else np.inf)
            return x[np.argmax(p) if find_max else np.argmin(p)]
        return f

    v, s = stat(x_of_extreme("volume_fraction", 0.1))
    row("density: x'/R of its maximum at y = 0.1 h", "0 (the centre)", v[0], s[0], near(0.0, 0.05), 2)

    # Fabric (Fig. 8).
    v, s = stat(lambda F: F.mean(F["fabric_xx"] + F["fabric_yy"], e.core()) / F.mean(F["fabric_xx"] + F["fabric_yy"], e.flanks()) - 1)
    row("fabric trace: core over flanks, minus 1", "> 0 (rises towards the centre)", v[0], s[0], sign(True), 3)
    base_axis = (np.abs(e.xr) < 0.15) & (e.yh > 0.05) & (e.yh < 0.2)
    top_axis = (np.abs(e.xr) < 0.15) & (e.yh > 0.5) & (e.yh < 0.7)
    v, s = stat(lambda F: F.mean(F["fabric_xx"] + F["fabric_yy"], base_axis) / F.mean(F["fabric_xx"] + F["fabric_yy"], top_axis) - 1)
    row("fabric trace on the axis: y < 0.2 h over 0.5-0.7 h, minus 1", "> 0 (rises towards the base)", v[0], s[0], sign(True), 3)

    v, s = stat(lambda F: F.mean(F.axes("fabric")[0], e.core()) - F.mean(F.axes("fabric")[0], e.flanks()))
    row("fabric deviatoric fraction: core minus flanks", "< 0 (lowest at the centre)", v[0], s[0], sign(False), 3)
    v, s = stat(lambda F: (F.mean(F.axes("fabric")[1], e.flanks(-1)), F.mean(F.axes("fabric")[1], e.flanks(1))))
    rows.append(("fabric major axis, tilt from the vertical on the left / right flank (deg)", "-40 / +40 (\"to the horizontal\")",
                 f"{fmt(v[0], s[0], 1)} / {fmt(v[1], s[1], 1)}", "see the note on orientations"))

    # Stress (Fig. 9).
    def centre_over_max(y):
        def f(F):
            x, p = F.profile(-F["stress_yy"], y)
            centre = np.nanmean(p[np.abs(x) < 0.05])
            return centre / np.nanmax(p[np.abs(x) < 0.8])
        return f

    for y in (0.0, 0.1, 0.2, 0.3, 0.5):
        v, s = stat(centre_over_max(y))
        rows.append((f"sigma_yy at the axis over its maximum, y = {y:g} h", "< 1 (a dip) up to some height" if y else "< 1 (the dip)",
                     fmt(v[0], s[0], 3), "dip (beyond 2 SE)" if v[0] < 1 - 2 * s[0] else "no dip resolved"))
    v, s = stat(x_of_extreme(lambda F: -F["stress_yy"], 0.0))
    row("x'/R of the sigma_yy maximum at the base (left side < 0)", "not given (Fig. 9A: about ±0.3)", v[0], s[0],
        lambda v_, s_: "compare with Fig. 9A", 2)
    def x_of_dip(y):
        def f(F):
            x, p = F.profile(-F["stress_yy"], y)
            p = np.where(np.isfinite(p), p, np.nan)
            left = np.where(x < 0, np.where(x > -0.6, p, -np.inf), -np.inf)
            right = np.where(x > 0, np.where(x < 0.6, p, -np.inf), -np.inf)
            lo, hi = x[np.nanargmax(left)], x[np.nanargmax(right)]
            between = np.where((x >= lo) & (x <= hi) & np.isfinite(p), p, np.inf)
            return x[np.argmin(between)]
        return f

    v, s = stat(x_of_dip(0.1))
    row("x'/R of the sigma_yy minimum between its two maxima at y = 0.1 h", "at the density maximum (the centre)",
        v[0], s[0], near(0.0, 0.05), 2)

    for name, mask, paper, target in (("core", e.core(), "0.2", 0.2), ("flanks", e.flanks(), "0.45", 0.45),
                                      ("surface layer", e.surface_layer(), "0.6", 0.6)):
        v, s = stat(lambda F, m=mask: F.mean(F.axes("stress")[0], m))
        row(f"stress anisotropy (s1 - s2)/(s1 + s2), {name}", paper, v[0], s[0], near(target, 0.05), 3)
    v, s = stat(lambda F: (F.mean(F.axes("stress")[1], e.flanks(-1)), F.mean(F.axes("stress")[1], e.flanks(1))))
    rows.append(("stress major axis, tilt from the vertical on the left / right flank (deg)", "-30 / +30",
                 f"{fmt(v[0], s[0], 1)} / {fmt(v[1], s[1], 1)}", "see the note on orientations"))
    fpa = e.report["compare"]["fpa_angle"]
    rows.append(("best-fit FPA angle psi (deg) against 45 - phi/2", f"FPA: {fpa['psi_fpa_deg']:.1f}",
                 fmt(fpa["psi_fit_deg"], fpa.get("psi_fit_deg_stderr", np.nan), 1),
                 "the axes are not the FPA's" if abs(fpa["psi_fit_deg"] - fpa["psi_fpa_deg"]) > 2 * fpa.get("psi_fit_deg_stderr", 0) else "agrees with FPA"))
    # FPA fixes the tilt at -+psi on either side: the spread of the tilt, mirrored to one side,
    # about its mean over the flanks is what FPA sets to zero.
    v, s = stat(lambda F: float(np.nanstd((F.axes("stress")[1] * np.sign(e.xr))[e.flanks()])))
    row("spread (sd) of the stress axis' tilt over the flanks, mirrored to one side (deg)", "not fixed (FPA: 0)",
        v[0], s[0], sign(True), 1)

    # RVE size (Figs. 5-6).
    rve = e.report["coarse"].get("rve_study", {})
    if rve:
        counts = [p["converged_grain_count"] for p in rve["points"]]
        rows.append(("RVE size at which stress, fabric, volume fraction converge (grains)", "100-200",
                     f"{min(counts):.0f}-{max(counts):.0f} (chosen {rve['chosen_grain_count']:.0f}; tolerance {rve['tolerance']:g}, members' mean)",
                     "differs: ours converges more slowly" if min(counts) > 200 else "agrees"))

    # Displacements and strains (Figs. 12-14).
    apex_region = e.yh > 0.7
    base_core = (e.yh < 0.2) & (np.abs(e.xr) < 0.3)
    v, s = stat(lambda F: F.mean(np.hypot(F["displacement_x"], F["displacement_y"]), apex_region)
                / F.mean(np.hypot(F["displacement_x"], F["displacement_y"]), base_core))
    row("|u| of the gravity change: y > 0.7 h over the base core", "> 1 (grows towards the tip)", v[0] - 1, s[0], sign(True), 2,
        "shown minus 1")

    def strain_centre_over_max(y):
        def f(F):
            x, p = F.profile(np.abs(F["strain_yy"]), y)  # the gravity reduction's (unloading) strain
            return np.nanmean(p[np.abs(x) < 0.05]) / np.nanmax(p[np.abs(x) < 0.8])
        return f

    for y in (0.1, 0.3):
        v, s = stat(strain_centre_over_max(y))
        rows.append((f"|strain_yy| at the axis over its maximum, y = {y:g} h", "< 1 (a dip) up to some height",
                     fmt(v[0], s[0], 3), "dip (beyond 2 SE)" if v[0] < 1 - 2 * s[0] else "no dip resolved"))
    v, s = stat(lambda F: (F.mean(F.axes("strain")[1], e.flanks(-1)), F.mean(F.axes("strain")[1], e.flanks(1))))
    rows.append(("strain major axis, tilt from the vertical on the left / right flank (deg)", "-45 / +45",
                 f"{fmt(v[0], s[0], 1)} / {fmt(v[1], s[1], 1)}", "see the note on orientations"))

    # Non-collinearity (Fig. 15).
    pile = e.yh < 0.9
    def misalign(F):
        ts, tf, te = F.axes("stress")[1], F.axes("fabric")[1], F.axes("strain")[1]
        return (F.mean(angle_between_axes(ts, te), pile), F.mean(angle_between_axes(ts, tf), pile),
                F.mean(angle_between_axes(te, tf), pile))
    v, s = stat(misalign)
    rows.append(("angle between major axes: stress-strain / stress-fabric / strain-fabric (deg)", "not collinear; fabric tilted most",
                 " / ".join(fmt(a, b, 1) for a, b in zip(v, s)),
                 "not collinear (each beyond 2 SE)" if np.all(v > 2 * s) else "partly collinear"))
    def mean_abs_tilts(F):
        return tuple(F.mean(np.abs(t), e.flanks()) for t in (F.axes("stress")[1], F.axes("strain")[1], F.axes("fabric")[1]))
    v, s = stat(mean_abs_tilts)
    most = ["stress", "strain", "fabric"][int(np.argmax(v))]
    rows.append(("mean |tilt| on the flanks: stress / strain / fabric (deg)", "fabric most (conclusions)",
                 " / ".join(fmt(a, b, 1) for a, b in zip(v, s)), f"{most} tilted most"))

    # tr F against nu C (eqs. 20-23, Fig. 16B).
    def slope(F):
        tr, vc = F["fabric_xx"] + F["fabric_yy"], F["volume_fraction"] * F["coordination"]
        ok = np.isfinite(tr) & np.isfinite(vc) & e.interior()
        return float(np.sum(tr[ok] * vc[ok]) / np.sum(vc[ok] ** 2))
    v, s = stat(slope)
    row("tr F / (nu C), least squares through 0 over points > 1 RVE radius deep, polydisperse 30 %", "g2 = 1.045 (eq. 23)", v[0], s[0], near(1.045, 0.01), 4)

    # Coordination.
    v, s = stat(lambda F: (F.mean(F["coordination"], e.core()), F.mean(F["coordination"], e.flanks())))
    rows.append(("coordination number: core / flanks", "not given", f"{fmt(v[0], s[0], 2)} / {fmt(v[1], s[1], 2)}", "-"))
    return rows


def comparison(e):
    """The models against the DEM ensemble: report.json's compare and fit sections."""
    c = e.report["compare"]
    rows = []
    for model in ("elastic", "fpa"):
        m = c["models"].get(model, {})
        for comp in ("xx", "yy", "xy"):
            k = f"relative_l2_stress_{comp}"
            if k in m:
                rows.append((model, f"relative L2 difference of sigma_{comp}", fmt(m[k], m.get(k + "_stderr", np.nan), 3)))
        k = "principal_axis_angle_mean_deg"
        if m.get(k) is not None:
            rows.append((model, "mean angle between the major stress axes (deg)", fmt(m[k], m.get(k + "_stderr", np.nan), 1)))
    for source, d in c["base_pressure_dip"].items():
        rows.append((source, "base sigma_yy: axis over maximum; x'/R of the maximum",
                     f"{d['centre_over_max']:.3f}; {d['x_of_max_over_R']:+.2f}"))
    fit = e.report.get("fit", {}).get("models", {}).get("isotropic")
    if fit:
        rows.append(("isotropic fit of the gravity change", "E (N/m), nu, 95 % interval over piles",
                     f"E = {fit['E_N_per_m']:.3g} [{fit['E_N_per_m_ci95'][0]:.3g}, {fit['E_N_per_m_ci95'][1]:.3g}], "
                     f"nu = {fit['nu']:.3f} [{fit['nu_ci95'][0]:.3f}, {fit['nu_ci95'][1]:.3f}], r2 = {fit['r2']:.2f}"))
    return rows


def markdown(e, rows, comp):
    seeds = ", ".join(str(m["seed"]) for m in e.report["ensemble"]["members"])
    lines = [f"Ensemble: {e.n} of the paper's 14 symmetric piles (seeds {seeds}); mesh {e.report['mesh'].get('kind', 'wedge')}, "
             f"RVE radius {e.attrs['rve_radius_m']:.4f} m, h = {e.h:.3f} m, R = {e.R:.3f} m. "
             "Errors: one jackknife standard error over the piles.", "",
             "| finding | paper | ours | verdict |", "|---|---|---|---|"]
    cell = lambda s: str(s).replace("|", "\\|")  # noqa: E731 - a bar inside a cell ends it
    lines += [f"| {cell(a)} | {cell(b)} | {cell(c)} | {cell(d)} |" for a, b, c, d in rows]
    lines += ["", "The models on the same mesh, against the DEM ensemble mean:", "",
              "| model | quantity | value |", "|---|---|---|"]
    lines += [f"| {a} | {b} | {c} |" for a, b, c in comp]
    return "\n".join(lines) + "\n"


def read_profiles(products):
    table = {}
    with gzip.open(os.path.join(products, "profiles.csv.gz"), "rt", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            key = (r["source"], r["quantity"], float(r["y_over_h"]))
            table.setdefault(key, []).append((float(r["x_m"]), float(r["value"]), float(r["stderr"] or 0.0)))
    return {k: np.array(sorted(v)) for k, v in table.items()}


def figures(e, products, outdir):
    """One PNG per paper figure with data behind it: cuts at the profile heights, mean with a
    band of one standard error; the models drawn over the DEM where they have the quantity."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    prof = read_profiles(products)
    heights = sorted({k[2] for k in prof if k[0] == "dem" and k[1] == "sigma_yy"})
    cmap = plt.get_cmap("viridis")
    panels = {
        "fig07_volume_fraction": [("volume_fraction", "volume fraction nu")],
        "fig08_fabric": [("fabric_trace", "tr F"), ("fabric_anisotropy", "deviatoric fraction of F"),
                         ("fabric_orientation_deg", "major axis from horizontal (deg)")],
        "fig09_stress": [("sigma_yy", "sigma_yy / rho g h"), ("stress_anisotropy", "stress anisotropy"),
                         ("stress_orientation_deg", "major axis from horizontal (deg)")],
        "fig12_displacement": [("displacement_x", "u_x (m)"), ("displacement_y", "u_y (m)")],
        "fig13_strain": [("strain_yy", "strain_yy")],
        "fig14_strain_orientation": [("strain_orientation_deg", "major axis from horizontal (deg)")],
        "fig15_misalignment": [("misalignment_stress_strain_deg", "stress-strain (deg)"),
                               ("misalignment_stress_fabric_deg", "stress-fabric (deg)"),
                               ("misalignment_strain_fabric_deg", "strain-fabric (deg)")],
    }
    os.makedirs(outdir, exist_ok=True)
    written = []
    for name, quantities in panels.items():
        fig, axes = plt.subplots(1, len(quantities), figsize=(5.2 * len(quantities), 4.0), squeeze=False)
        for ax, (q, label) in zip(axes[0], quantities):
            for i, y in enumerate(heights):
                colour = cmap(i / max(1, len(heights) - 1))
                d = prof.get(("dem", q, y))
                if d is None or len(d) == 0:
                    continue
                ax.plot(d[:, 0], d[:, 1], color=colour, label=f"DEM y = {y:g} h")
                ax.fill_between(d[:, 0], d[:, 1] - d[:, 2], d[:, 1] + d[:, 2], color=colour, alpha=0.25, lw=0)
                for model, style in (("elastic", "--"), ("fpa", ":")):
                    m = prof.get((model, q, y))
                    if m is not None and len(m) and y in (heights[0], heights[len(heights) // 2]):
                        ax.plot(m[:, 0], m[:, 1], style, color=colour, lw=1.2, label=f"{model} y = {y:g} h")
            if q == "volume_fraction":  # the surface RVEs of a mean wedge are no volume fraction
                ax.set_ylim(0.6, 0.95)
            ax.set_xlabel("x (m)")
            ax.set_ylabel(label)
        axes[0][0].legend(fontsize=6, ncol=2)
        bands = "mean ± 1 SE" if name != "fig15_misalignment" else "mean (profiles.csv gives these angles no SE)"
        fig.suptitle(f"{name.split('_', 1)[0].replace('fig', 'Fig. ')}: {e.n} symmetric piles, {bands}")
        fig.tight_layout()
        path = os.path.join(outdir, name + ".png")
        fig.savefig(path + ".tmp.png", dpi=110)
        os.replace(path + ".tmp.png", path)
        plt.close(fig)
        written.append(path)

    # Fig. 16B: tr F against nu C at every point, and the line of slope g2.
    F = Fields(e, e.mean_fields(sorted(e.piles)))
    tr, vc = F["fabric_xx"] + F["fabric_yy"], F["volume_fraction"] * F["coordination"]
    ok = np.isfinite(tr) & np.isfinite(vc) & e.interior()
    fig, ax = plt.subplots(figsize=(4.6, 4.2))
    ax.plot(tr[ok], vc[ok], ".", ms=2, color="0.3")
    lim = [0.95 * min(tr[ok].min(), vc[ok].min()), 1.05 * max(tr[ok].max(), vc[ok].max())]
    ax.plot(lim, lim, "k--", lw=1, label="nu C = tr F")
    ax.plot(lim, np.array(lim) / 1.045, "r:", lw=1, label="tr F = 1.045 nu C (paper, eq. 23)")
    ax.set_xlabel("tr F")
    ax.set_ylabel("nu C")
    ax.legend(fontsize=7)
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_title(f"Fig. 16B: {e.n} polydisperse piles, points > 1 RVE radius deep", fontsize=9)
    fig.tight_layout()
    path = os.path.join(outdir, "fig16b_fabric_trace.png")
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
    plt.close(fig)
    written.append(path)
    return written


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study", nargs="?", default=os.path.join(ROOT, "docs", "studies", "paper", "symmetric"))
    parser.add_argument("--doc", default=os.path.join(ROOT, "docs", "studies", "paper.md"))
    args = parser.parse_args()
    products = os.path.join(args.study, "products")
    e = Ensemble(products)
    table = markdown(e, findings(e), comparison(e))
    with open(args.doc, encoding="utf-8") as f:
        doc = f.read()
    begin, end = "<!-- table: studies/paper/tables.py -->\n", "<!-- end of table -->"
    if begin not in doc or end not in doc:
        sys.exit(f"{args.doc}: no table markers ({begin.strip()} ... {end})")
    doc = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: begin + table + end, doc, flags=re.S)
    with open(args.doc + ".tmp", "w", encoding="utf-8") as f:
        f.write(doc)
    os.replace(args.doc + ".tmp", args.doc)
    print(f"tables.py: {len(table.splitlines())} lines of table -> {args.doc}")
    for path in figures(e, products, os.path.join(os.path.dirname(args.doc), "paper")):
        print("tables.py: wrote", path)


if __name__ == "__main__":
    main()
