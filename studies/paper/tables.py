#!/usr/bin/python3
"""The paper study's tables and figures, from the committed products alone (no pouring, no
pilelab binary): docs/studies/paper.md's tables between its markers, and the PNGs in
docs/studies/paper/.

    /usr/bin/python3 studies/paper/tables.py [ROOT] [--doc docs/studies/paper.md] [--figures DIR]

ROOT (docs/studies/paper) holds a folder per ensemble (symmetric, asymmetric, monodisperse,
symmetric-paper-step, asymmetric-travel-0.5),
each with the products of studies/paper/stages.py: products/ (fields.h5 with every pile's own
fields in /piles/K, report.json, profiles.csv.gz, rve_study.csv.gz, scene.toml), and where they
were made, products_rve_study/ (the RVE of the size the RVE study chooses) and
products_smooth_base/ (elasticity on a smooth base). An ensemble without products is listed
as not yet measured.

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

    def __init__(self, products, kind="symmetric"):
        self.kind = kind
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
        self.half_widths = (left, right)

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

    def depth_below_flank(self, x, y_over_h):
        """Vertical depth [m] below the wedge's flank of points at x [m] and height y / h."""
        x = np.asarray(x, dtype=float) - self.apex
        xr = np.where(x < 0, x / self.half_widths[0], x / self.half_widths[1])
        return (1 - np.abs(xr) - y_over_h) * self.h

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

    def replicates(self, function):
        """function(Fields) -> float or tuple of floats; returns (value, leave-one-out values):
        the statistic of the mean over all piles, and over all but pile k for each k (rows in the
        order of the piles' keys; None with fewer than two piles)."""
        keys = sorted(self.piles)
        full = np.atleast_1d(np.asarray(function(Fields(self, self.mean_fields(keys))), dtype=float))
        if self.n < 2:
            return full, None
        leave_out = np.array([np.atleast_1d(function(Fields(self, self.mean_fields([j for j in keys if j != k]))))
                              for k in keys], dtype=float)
        return full, leave_out

    def statistic(self, function):
        """function(Fields) -> float or tuple of floats; returns (value, stderr) arrays."""
        full, leave_out = self.replicates(function)
        return full, jackknife_se(leave_out) if leave_out is not None else np.full_like(full, np.nan)


def jackknife_se(leave_out):
    """The jackknife standard error from the leave-one-out values (rows: the piles)."""
    n = len(leave_out)
    return np.sqrt((n - 1) / n * np.sum((leave_out - leave_out.mean(axis=0)) ** 2, axis=0))


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
        tilt = (theta - 90.0 + 90.0) % 180.0 - 90.0  # the major axis from the vertical, in [-90, 90)
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


# --- The rows -------------------------------------------------------------------------------
# Each row is (finding, paper, ours, verdict); `ours` holds every number with its standard error.

def near(target, tol=0.0):
    """Agrees when the paper's value (which carries no error) lies within 2 SE (plus the
    precision to which the paper states it) of ours."""
    return lambda v, s: "agrees within errors" if abs(v - target) <= 2 * s + tol else (
        "differs" + (f" ({(v - target) / s:+.1f} SE)" if s > 0 else ""))


def sign(expected_positive):
    return lambda v, s: ("agrees (beyond 2 SE)" if (v > 2 * s if expected_positive else v < -2 * s)
                         else "within 2 SE of none: not resolved" if abs(v) <= 2 * s else "opposite sign")


def no_verdict(text):
    return lambda v, s: text


class Rows(list):
    """The rows of one ensemble's table, built from statistics of its mean fields."""

    def __init__(self, e):
        super().__init__()
        self.e = e

    def add(self, finding, paper, function, verdict, digits=2, note="", shift=0.0, resolution=0.0):
        """One number: function(Fields) -> float, shown minus `shift`. A statistic that can take
        only values `resolution` apart (a position read off the profile's bins) carries at least
        the error of that rounding, resolution / sqrt(12)."""
        v, s = self.e.statistic(function)
        s = np.hypot(s, resolution / np.sqrt(12))
        text = verdict(v[0] - shift, s[0]) + (f"; {note}" if note else "")
        self.append((finding, paper, fmt(v[0] - shift, s[0], digits), text))
        return v[0], s[0]

    def add_many(self, finding, paper, function, verdict, digits=1, resolution=0.0):
        """Several numbers in one cell: function(Fields) -> tuple; verdict(values, errors)."""
        v, s = self.e.statistic(function)
        s = np.hypot(s, resolution / np.sqrt(12))
        self.append((finding, paper, " / ".join(fmt(a, b, digits) for a, b in zip(v, s)), verdict(v, s)))
        return v, s

    def repose(self, targets, paper):
        ens = self.e.report["ensemble"]
        for side, name in (("left", "left"), ("right", "right"), ("pile_mean", "mean of both flanks")):
            s = ens[f"repose_angle_{side}_deg"]
            target = targets.get(side)
            verdict = near(target, 0.5) if target is not None else no_verdict("-")
            self.append((f"repose angle, {name} (deg)", paper.get(side, "not given"), fmt(s["mean"], s["standard_error"], 1),
                         verdict(s["mean"], s["standard_error"]) + "; SE over the piles' own angles"))

    def base_dips(self, heights, under="the axis"):
        for y in heights:
            v, s = self.e.statistic(centre_over_max(y))
            self.append((f"sigma_yy under {under} over its maximum, y = {y:g} h", "< 1 (a dip) up to some height" if y else "< 1 (the dip)",
                         fmt(v[0], s[0], 3), "dip (beyond 2 SE)" if v[0] < 1 - 2 * s[0] else "no dip resolved"))

    def base_plateau(self, heights, under="the axis"):
        """The dip by region means instead of single bins: sigma_yy over |x'| < 0.1 over its mean
        over 0.15 < |x'| < 0.35 (about where the paper's maxima are), minus 1: four bins over
        eight, so far less noise than the centre bin over the highest bin, which noise also
        biases. A pressure proportional to the height of the pile above the point, (1 - |x'| -
        y/h) h, gives (0.95 - y/h) / (0.75 - y/h) - 1 (+0.27 at the base); a flat top 0; a dip
        less than 0."""
        for y in heights:
            column = (0.95 - y) / (0.75 - y) - 1
            self.add(f"sigma_yy under {under}, |x'| < 0.1, over its mean at 0.15 < |x'| < 0.35, minus 1, y = {y:g} h",
                     f"< 0 (the dip; pressure proportional to height: +{column:.2f})", centre_over_ring(y),
                     lambda v, s: ("dip (beyond 2 SE)" if v < -2 * s else "flat top within 2 SE, no dip" if v <= 2 * s
                                   else "centre higher: no dip"), 3)

    def coordination(self):
        e = self.e
        self.add_many("coordination number: core / flanks", "not given",
                      lambda F: (F.mean(F["coordination"], e.core()), F.mean(F["coordination"], e.flanks())),
                      lambda v, s: "-", 2)

    def fabric_scatter(self):
        """How closely tr F follows nu C: the relative sd of their ratio over the interior."""
        e = self.e
        return self.add("scatter of tr F / (nu C) over points > 1 RVE radius deep (relative sd)",
                        "mono: on one line (Fig. 16A); poly: not (Fig. 16B)", lambda F: ratio_scatter(F, e), no_verdict("-"), 4)


BIN = 0.05  # the width in x' of the profiles' bins (Fields.profile)


def centre_over_max(y):
    def f(F):
        x, p = F.profile(-F["stress_yy"], y)
        with _quiet():
            return np.nanmean(p[np.abs(x) < 0.05]) / np.nanmax(p[np.abs(x) < 0.8])
    return f


def centre_over_ring(y):
    def f(F):
        x, p = F.profile(-F["stress_yy"], y)
        ring = (np.abs(x) > 0.15) & (np.abs(x) < 0.35)
        with _quiet():
            return np.nanmean(p[np.abs(x) < 0.1]) / np.nanmean(p[ring]) - 1
    return f


def x_of_extreme(q, y, find_max=True, side=0):
    """x' of the profile's extreme at height y (|x'| < 0.8; one side only if side is -1 or 1)."""
    def f(F):
        x, p = F.profile(F[q] if isinstance(q, str) else q(F), y)
        inner = (np.abs(x) < 0.8) & ((np.sign(x) == side) if side else True)
        p = np.where(inner & np.isfinite(p), p, -np.inf if find_max else np.inf)
        return x[np.argmax(p) if find_max else np.argmin(p)]
    return f


def x_of_dip(y):
    """x' of the lowest sigma_yy between its maxima on the two sides at height y."""
    def f(F):
        x, p = F.profile(-F["stress_yy"], y)
        left = np.where((x < 0) & (x > -0.6) & np.isfinite(p), p, -np.inf)
        right = np.where((x > 0) & (x < 0.6) & np.isfinite(p), p, -np.inf)
        lo, hi = x[np.argmax(left)], x[np.argmax(right)]
        between = np.where((x >= lo) & (x <= hi) & np.isfinite(p), p, np.inf)
        return x[np.argmin(between)]
    return f


def trace_and_nu_c(F, e):
    tr, vc = F["fabric_xx"] + F["fabric_yy"], F["volume_fraction"] * F["coordination"]
    ok = np.isfinite(tr) & np.isfinite(vc) & e.interior()
    return tr[ok], vc[ok]


def g2_slope(F, e):
    """tr F / (nu C) by least squares through the origin (eq. 23)."""
    tr, vc = trace_and_nu_c(F, e)
    return float(np.sum(tr * vc) / np.sum(vc ** 2))


def ratio_scatter(F, e):
    tr, vc = trace_and_nu_c(F, e)
    ratio = tr / vc
    return float(np.std(ratio) / np.mean(ratio))


def symmetric_rows(e):
    r = Rows(e)
    r.repose({"left": 28.0, "right": 28.0, "pile_mean": 28.0},
             {"left": "about 28", "right": "about 28", "pile_mean": "about 28"})

    # Density (Fig. 7).
    r.add("density: core over the outer layer (1-2 RVE radii deep), minus 1", "0.08-0.10",
          lambda F: F.mean(F["volume_fraction"], e.core()) / F.mean(F["volume_fraction"], e.outer_layer()) - 1, near(0.09, 0.01), 3)
    r.add("density: x'/R of its maximum at y = 0.1 h", "0 (the centre)", x_of_extreme("volume_fraction", 0.1), near(0.0, 0.05),
          resolution=BIN)

    # Fabric (Fig. 8).
    trace = lambda F: F["fabric_xx"] + F["fabric_yy"]  # noqa: E731
    r.add("fabric trace: core over flanks, minus 1", "> 0 (rises towards the centre)",
          lambda F: F.mean(trace(F), e.core()) / F.mean(trace(F), e.flanks()) - 1, sign(True), 3)
    base_axis = (np.abs(e.xr) < 0.15) & (e.yh > 0.05) & (e.yh < 0.2)
    top_axis = (np.abs(e.xr) < 0.15) & (e.yh > 0.5) & (e.yh < 0.7)
    r.add("fabric trace on the axis: y < 0.2 h over 0.5-0.7 h, minus 1", "> 0 (rises towards the base)",
          lambda F: F.mean(trace(F), base_axis) / F.mean(trace(F), top_axis) - 1, sign(True), 3)
    r.add("fabric deviatoric fraction: core minus flanks", "< 0 (lowest at the centre)",
          lambda F: F.mean(F.axes("fabric")[0], e.core()) - F.mean(F.axes("fabric")[0], e.flanks()), sign(False), 3)
    r.add_many("fabric major axis, tilt from the vertical on the left / right flank (deg)", "-40 / +40 (\"to the horizontal\")",
               lambda F: (F.mean(F.axes("fabric")[1], e.flanks(-1)), F.mean(F.axes("fabric")[1], e.flanks(1))),
               lambda v, s: "see the note on orientations")

    # Stress (Fig. 9).
    r.base_dips((0.0, 0.1, 0.2, 0.3, 0.5))
    r.base_plateau((0.0, 0.1))
    r.add_many("x'/R of the sigma_yy maxima at the base, left / right", "not given (Fig. 9A: about -0.3 / +0.3)",
               lambda F: (x_of_extreme(lambda G: -G["stress_yy"], 0.0, side=-1)(F),
                          x_of_extreme(lambda G: -G["stress_yy"], 0.0, side=1)(F)),
               lambda v, s: "compare with Fig. 9A", 2, resolution=BIN)
    r.add("x'/R of the sigma_yy minimum between its two maxima at y = 0.1 h", "at the density maximum (the centre)",
          x_of_dip(0.1), near(0.0, 0.05), resolution=BIN)
    for name, mask, paper, target in (("core", e.core(), "0.2", 0.2), ("flanks", e.flanks(), "0.45", 0.45),
                                      ("surface layer", e.surface_layer(), "0.6", 0.6)):
        r.add(f"stress anisotropy (s1 - s2)/(s1 + s2), {name}", paper, lambda F, m=mask: F.mean(F.axes("stress")[0], m),
              near(target, 0.05), 3)
    r.add_many("stress major axis, tilt from the vertical on the left / right flank (deg)", "-30 / +30",
               lambda F: (F.mean(F.axes("stress")[1], e.flanks(-1)), F.mean(F.axes("stress")[1], e.flanks(1))),
               lambda v, s: "see the note on orientations")
    fpa_angle_row(r)
    # FPA fixes the tilt at -+psi on either side: the spread of the tilt, mirrored to one side,
    # about its mean over the flanks is what FPA sets to zero.
    r.add("spread (sd) of the stress axis' tilt over the flanks, mirrored to one side (deg)", "not fixed (FPA: 0)",
          lambda F: float(np.nanstd((F.axes("stress")[1] * np.sign(e.xr))[e.flanks()])), sign(True), 1)

    # RVE size (Figs. 5-6).
    rve = e.report["coarse"].get("rve_study", {})
    if rve:
        counts = [p["converged_grain_count"] for p in rve["points"]]
        r.append(("RVE size at which stress, strain, fabric, volume fraction converge (grains)", "100-200",
                  f"{min(counts):.0f}-{max(counts):.0f} at {len(counts)} points (chosen {rve['chosen_grain_count']:.0f}; "
                  f"tolerance {rve['tolerance']:g}, members' mean)",
                  "differs: ours converges more slowly" if min(counts) > 200 else "agrees"))

    # Displacements and strains (Figs. 12-14).
    apex_region = e.yh > 0.7
    base_core = (e.yh < 0.2) & (np.abs(e.xr) < 0.3)
    u = lambda F: np.hypot(F["displacement_x"], F["displacement_y"])  # noqa: E731
    r.add("|u| of the gravity change: y > 0.7 h over the base core, minus 1", "> 0 (grows towards the tip)",
          lambda F: F.mean(u(F), apex_region) / F.mean(u(F), base_core), sign(True), 2, shift=1.0)

    def strain_centre_over_max(y):
        def f(F):
            x, p = F.profile(np.abs(F["strain_yy"]), y)  # the gravity reduction's (unloading) strain
            with _quiet():
                return np.nanmean(p[np.abs(x) < 0.05]) / np.nanmax(p[np.abs(x) < 0.8])
        return f

    for y in (0.1, 0.3):
        v, s = e.statistic(strain_centre_over_max(y))
        r.append((f"|strain_yy| at the axis over its maximum, y = {y:g} h", "< 1 (a dip) up to some height",
                  fmt(v[0], s[0], 3), "dip (beyond 2 SE)" if v[0] < 1 - 2 * s[0] else "no dip resolved"))
    r.add_many("strain major axis, tilt from the vertical on the left / right flank (deg)", "-45 / +45",
               lambda F: (F.mean(F.axes("strain")[1], e.flanks(-1)), F.mean(F.axes("strain")[1], e.flanks(1))),
               lambda v, s: "see the note on orientations")

    # Non-collinearity (Fig. 15).
    pile = e.yh < 0.9

    def misalign(F):
        ts, tf, te = F.axes("stress")[1], F.axes("fabric")[1], F.axes("strain")[1]
        return (F.mean(angle_between_axes(ts, te), pile), F.mean(angle_between_axes(ts, tf), pile),
                F.mean(angle_between_axes(te, tf), pile))
    r.add_many("angle between major axes: stress-strain / stress-fabric / strain-fabric (deg)", "not collinear; fabric tilted most",
               misalign, lambda v, s: "not collinear (each beyond 2 SE)" if np.all(v > 2 * s) else "partly collinear")
    r.add_many("mean |tilt| on the flanks: stress / strain / fabric (deg)", "fabric most (conclusions)",
               lambda F: tuple(F.mean(np.abs(F.axes(k)[1]), e.flanks()) for k in ("stress", "strain", "fabric")),
               lambda v, s: f"{['stress', 'strain', 'fabric'][int(np.argmax(v))]} tilted most")

    # tr F against nu C and nu (eqs. 20-23, Figs. 16B and 17).
    r.add("tr F / (nu C), least squares through 0 over points > 1 RVE radius deep, polydisperse 30 %", "g2 = 1.045 (eq. 23)",
          lambda F: g2_slope(F, e), near(1.045, 0.01), 4)
    r.fabric_scatter()

    def trace_nu_correlation(F):
        tr, nu = F["fabric_xx"] + F["fabric_yy"], F["volume_fraction"]
        ok = np.isfinite(tr) & np.isfinite(nu) & e.interior()
        return float(np.corrcoef(tr[ok], nu[ok])[0, 1])
    r.add("correlation of tr F with nu over points > 1 RVE radius deep (Pearson r)", "roughly linear (Fig. 17)",
          trace_nu_correlation, sign(True), 2)
    r.coordination()
    return r


def fpa_angle_row(r):
    fpa = r.e.report["compare"]["fpa_angle"]
    se = fpa.get("psi_fit_deg_stderr", np.nan)
    r.append(("best-fit FPA angle psi (deg) against 45 - phi/2", f"FPA: {fpa['psi_fpa_deg']:.1f}", fmt(fpa["psi_fit_deg"], se, 1),
              "the axes are not the FPA's" if abs(fpa["psi_fit_deg"] - fpa["psi_fpa_deg"]) > 2 * se else "agrees with FPA"))


def asymmetric_rows(e):
    """Section 5 and Fig. 11: the flanks, and the pressure under the pile poured from a moving
    funnel (x' is measured from the apex, in each side's own half-width)."""
    r = Rows(e)
    r.repose({"left": 28.0, "right": 21.0}, {"left": "28", "right": "21", "pile_mean": "24.5 (mean of 28 and 21)"})
    # The asymmetry pile by pile: each pile's flanks share its history, so their difference is
    # far less noisy than the difference of the two flanks' ensemble means.
    diff = np.array([m["repose_angle_left_deg"] - m["repose_angle_right_deg"] for m in e.report["ensemble"]["members"]])
    se = float(np.std(diff, ddof=1) / np.sqrt(len(diff))) if len(diff) > 1 else np.nan
    r.append(("repose angle, left minus right, pile by pile (deg)", "7 (28 - 21)", fmt(float(diff.mean()), se, 1),
              ("left steeper (beyond 2 SE)" if diff.mean() > 2 * se else "right steeper (beyond 2 SE)" if diff.mean() < -2 * se
               else "no asymmetry resolved") + "; SE over the piles' own differences"))
    r.base_dips((0.0, 0.1, 0.2, 0.3), under="the apex")
    r.base_plateau((0.0, 0.1), under="the apex")
    r.add_many("x'/R of the sigma_yy maxima at the base, left / right", "not given (asymmetric, Fig. 11)",
               lambda F: (x_of_extreme(lambda G: -G["stress_yy"], 0.0, side=-1)(F), x_of_extreme(lambda G: -G["stress_yy"], 0.0, side=1)(F)),
               lambda v, s: "-", 2, resolution=BIN)

    def maxima_ratio(F):
        x, p = F.profile(-F["stress_yy"], 0.0)
        return np.nanmax(np.where((x < 0) & (x > -0.8), p, np.nan)) / np.nanmax(np.where((x > 0) & (x < 0.8), p, np.nan))
    r.add("base sigma_yy: left maximum over right maximum, minus 1", "asymmetric (not given)", maxima_ratio,
          lambda v, s: "asymmetric (beyond 2 SE)" if abs(v) > 2 * s else "no asymmetry resolved", 3, shift=1.0)
    r.add("x'/R of the sigma_yy minimum between its two maxima at the base", "beneath the tip (0)", x_of_dip(0.0), near(0.0, 0.05),
          resolution=BIN)
    r.add_many("stress major axis, tilt from the vertical on the left / right flank (deg)", "not given",
               lambda F: (F.mean(F.axes("stress")[1], e.flanks(-1)), F.mean(F.axes("stress")[1], e.flanks(1))),
               lambda v, s: "see the note on orientations")
    fpa_angle_row(r)
    r.coordination()
    return r


def monodisperse_rows(e):
    """Fig. 16A and eq. (20): tr F = nu C for grains of one size."""
    r = Rows(e)
    r.repose({}, {})
    r.add("tr F / (nu C), least squares through 0 over points > 1 RVE radius deep, monodisperse", "1 (eq. 20)",
          lambda F: g2_slope(F, e), near(1.0, 0.01), 4)
    r.fabric_scatter()
    r.coordination()
    return r


ENSEMBLES = {
    # kind: (heading, the paper's count, rows)
    "symmetric": ("Symmetric piles (section 2)", 14, symmetric_rows),
    "asymmetric": ("Asymmetric piles (section 5, Fig. 11)", 7, asymmetric_rows),
    "monodisperse": ("Monodisperse piles (Fig. 16A, eq. 20)", 7, monodisperse_rows),
    # Not the paper's: the symmetric scene at the paper's own 2e-6 s (Verlet), the test of the
    # default step on the paper pile (docs/studies/speed_accuracy.md); the count is its own.
    "symmetric-paper-step": ("Symmetric piles at the paper's time step, 2e-6 s (the default step's test)", 4,
                             symmetric_rows),
    # Not the paper's: its asymmetric scene with the funnel travelling 0.5 R, where small piles
    # were asymmetric (docs/studies/funnel_scan.md); "the paper's count" is that of section 5.
    "asymmetric-travel-0.5": ("Asymmetric piles, the funnel travelling 0.5 R (docs/studies/funnel_scan.md)", 7,
                              asymmetric_rows),
}


def step_confirmation(default, paper_step):
    """The paper pile at the paper's 2e-6 s against the default step (two Ensembles of the
    symmetric scene): (quantity, default, paper's step, difference, verdict) rows. The piles are
    different realisations, so the difference's error is the two standard errors in quadrature."""
    def angle(e):
        a = e.report["ensemble"]["repose_angle_pile_mean_deg"]
        return a["mean"], a["standard_error"]

    def field(function):
        def f(e):
            v, s = e.statistic(lambda F: function(F, e))
            return v[0], s[0]
        return f

    def tilt(F, e):
        t = F.axes("stress")[1]
        return F.mean(t * np.sign(e.xr), e.flanks())  # mirrored: both flanks' tilts counted alike

    quantities = [
        ("repose angle, mean of both flanks (deg)", angle, 1),
        ("stress major axis, tilt on the flanks, mirrored (deg)", field(tilt), 1),
        ("stress anisotropy (s1 - s2)/(s1 + s2), core", field(lambda F, e: F.mean(F.axes("stress")[0], e.core())), 3),
        ("fabric trace, core", field(lambda F, e: F.mean(F["fabric_xx"] + F["fabric_yy"], e.core())), 3),
        ("volume fraction, core", field(lambda F, e: F.mean(F["volume_fraction"], e.core())), 4),
        ("base sigma_yy, |x'| < 0.1 over 0.15 < |x'| < 0.35, minus 1", field(lambda F, e: centre_over_ring(0.0)(F)), 3),
        ("coordination number, core", field(lambda F, e: F.mean(F["coordination"], e.core())), 2),
    ]
    rows = []
    for label, measure, digits in quantities:
        (a, sa), (b, sb) = measure(default), measure(paper_step)
        d, sd = b - a, float(np.hypot(sa, sb))
        rows.append((label, fmt(a, sa, digits), fmt(b, sb, digits), fmt(d, sd, digits),
                     "differs (beyond 2 SE)" if abs(d) > 2 * sd else "no effect beyond 2 SE"))
    return rows


def with_rve_study_column(rows, rows_rve):
    """(finding, paper, ours, ours at the RVE study's size, verdict) from two row lists."""
    by_finding = {row[0]: row[2] for row in (rows_rve or [])}
    return [(f, p, o, by_finding.get(f, "-"), v) for f, p, o, v in rows]


def comparison(e, smooth):
    """The models against the DEM ensemble: report.json's compare and fit sections (smooth: the
    report of the same ensemble with a smooth base under elasticity)."""
    sources = [("elastic (rough base)", e.report, "elastic")]
    if smooth is not None:
        sources.append(("elastic (smooth base)", smooth, "elastic"))
    sources.append(("FPA", e.report, "fpa"))
    rows = []
    for label, report, model in sources:
        m = report["compare"]["models"].get(model, {})
        for comp in ("xx", "yy", "xy"):
            k = f"relative_l2_stress_{comp}"
            if k in m:
                rows.append((label, f"relative L2 difference of sigma_{comp}", fmt(m[k], m.get(k + "_stderr", np.nan), 3)))
        k = "principal_axis_angle_mean_deg"
        if m.get(k) is not None:
            rows.append((label, "mean angle between the major stress axes (deg)", fmt(m[k], m.get(k + "_stderr", np.nan), 1)))
        d = report["compare"]["base_pressure_dip"].get(model)
        if d:
            rows.append((label, "base sigma_yy: axis over maximum; x'/R of the maximum (the model's own, no ensemble error)",
                         f"{d['centre_over_max']:.3f}; {d['x_of_max_over_R']:+.2f}"))
    fit = e.report.get("fit", {}).get("models", {}).get("isotropic")
    if fit:
        rows.append(("isotropic fit of the gravity change", "E (N/m), nu, 95 % interval over piles",
                     f"E = {fit['E_N_per_m']:.3g} [{fit['E_N_per_m_ci95'][0]:.3g}, {fit['E_N_per_m_ci95'][1]:.3g}], "
                     f"nu = {fit['nu']:.3f} [{fit['nu_ci95'][0]:.3f}, {fit['nu_ci95'][1]:.3f}], r2 = {fit['r2']:.2f}"))
    return rows


def markdown(sections):
    """sections: (kind, ensemble, rows with the RVE column, comparison rows, RVE-study grains)."""
    cell = lambda s: str(s).replace("|", "\\|")  # noqa: E731 - a bar inside a cell ends it
    lines = []
    for kind, e, rows, comp, rve_grains in sections:
        heading, count, _ = ENSEMBLES[kind]
        seeds = ", ".join(str(m["seed"]) for m in e.report["ensemble"]["members"])
        lines += [f"### {heading}", "",
                  f"{e.n} of {count} piles (seeds {seeds}); mesh {e.report['mesh'].get('kind', 'wedge')}, "
                  f"RVE radius {e.attrs['rve_radius_m']:.4f} m (the paper's 150 grains), h = {e.h:.3f} m, R = {e.R:.3f} m. "
                  "Errors: one jackknife standard error over the piles.", "",
                  f"| finding | paper | ours | ours, RVE of {rve_grains} | verdict |", "|---|---|---|---|---|"]
        lines += ["| " + " | ".join(cell(c) for c in row) + " |" for row in rows]
        lines += ["", "The models on the same mesh, against the DEM ensemble mean:", "",
                  "| model | quantity | value |", "|---|---|---|"]
        lines += ["| " + " | ".join(cell(c) for c in row) + " |" for row in comp]
        lines.append("")
    measured = {s[0]: s[1] for s in sections}
    if "symmetric" in measured and "symmetric-paper-step" in measured:
        lines += ["### The default step against the paper's, on the paper pile", "",
                  f"The {measured['symmetric-paper-step'].n} piles at the paper's 2e-6 s against the "
                  f"{measured['symmetric'].n} at the default step (leapfrog, 0.8 of its limit); both with eq. A.2 as "
                  "written, so the paper's step is the paper's contact law exactly. The difference's error is the two "
                  "standard errors in quadrature (unpaired, so conservative); with few piles the jackknife error has few degrees "
                  "of freedom, and two of them are a weaker test than on many.", "",
                  "| quantity | default step | the paper's step | the paper's step minus the default | verdict |", "|---|---|---|---|---|"]
        lines += ["| " + " | ".join(cell(c) for c in row) + " |"
                  for row in step_confirmation(measured["symmetric"], measured["symmetric-paper-step"])]
        lines.append("")
    missing = [k for k in ENSEMBLES if k not in {s[0] for s in sections}]
    if missing:
        lines += [f"Not yet measured: the {', '.join(missing)} ensemble{'s' if len(missing) > 1 else ''} "
                  f"(no products yet); {'their' if len(missing) > 1 else 'its'} rows are missing, not estimated.", ""]
    return "\n".join(lines)


# --- The figures ----------------------------------------------------------------------------

def read_profiles(products):
    table = {}
    with gzip.open(os.path.join(products, "profiles.csv.gz"), "rt", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            key = (r["source"], r["quantity"], float(r["y_over_h"]))
            table.setdefault(key, []).append((float(r["x_m"]), float(r["value"]), float(r["stderr"] or 0.0)))
    return {k: np.array(sorted(v)) for k, v in table.items()}


def save(fig, outdir, name, written):
    path = os.path.join(outdir, name + ".png")
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
    written.append(path)


def cut_figures(plt, e, prof, smooth_prof, panels, outdir, what, written):
    """Horizontal cuts at the profile heights: mean with a band of one standard error, the
    models drawn over the DEM at two heights where they have the quantity."""
    heights = sorted({k[2] for k in prof if k[0] == "dem" and k[1] == "sigma_yy"})
    cmap = plt.get_cmap("viridis")
    models = [("elastic", "--", prof), ("fpa", ":", prof)]
    if smooth_prof is not None:
        models.insert(1, ("elastic", "-.", smooth_prof))
    for name, quantities in panels.items():
        fig, axes = plt.subplots(1, len(quantities), figsize=(5.2 * len(quantities), 4.0), squeeze=False)
        for ax, (q, label) in zip(axes[0], quantities):
            for i, y in enumerate(heights):
                colour = cmap(i / max(1, len(heights) - 1))
                d = prof.get(("dem", q, y))
                if d is None or len(d) == 0:
                    continue
                if q == "volume_fraction":
                    # Within an RVE radius of the mean wedge's flank, a member's own surface lies
                    # above or below it, and grain area over RVE area is no volume fraction.
                    d = d[e.depth_below_flank(d[:, 0], y) > float(e.attrs["rve_radius_m"])]
                    if len(d) == 0:
                        continue
                ax.plot(d[:, 0], d[:, 1], color=colour, label=f"DEM y = {y:g} h")
                ax.fill_between(d[:, 0], d[:, 1] - d[:, 2], d[:, 1] + d[:, 2], color=colour, alpha=0.25, lw=0)
                for model, style, table in models:
                    m = table.get((model, q, y))
                    if m is not None and len(m) and y in (heights[0], heights[len(heights) // 2]):
                        base = "" if model != "elastic" else (" smooth" if table is smooth_prof else " rough")
                        ax.plot(m[:, 0], m[:, 1], style, color=colour, lw=1.2, label=f"{model}{base} y = {y:g} h")
            if q == "volume_fraction":
                ax.set_title("points deeper than one RVE radius below the flank", fontsize=8)
            ax.set_xlabel("x (m)")
            ax.set_ylabel(label)
        axes[0][0].legend(fontsize=6, ncol=2)
        bands = "mean ± 1 SE" if "misalignment" not in name else "mean (profiles.csv gives these angles no SE)"
        fig.suptitle(f"{name.split('_', 1)[0].replace('fig', 'Fig. ')}: {e.n} {what} piles, {bands}")
        fig.tight_layout()
        save(fig, outdir, name, written)
        plt.close(fig)


def trace_figure(plt, e, outdir, name, title, slope, slope_label, written):
    """tr F against nu C at every point more than one RVE radius deep (Fig. 16)."""
    F = Fields(e, e.mean_fields(sorted(e.piles)))
    tr, vc = trace_and_nu_c(F, e)
    fig, ax = plt.subplots(figsize=(4.6, 4.2))
    ax.plot(tr, vc, ".", ms=2, color="0.3")
    lim = [0.95 * min(tr.min(), vc.min()), 1.05 * max(tr.max(), vc.max())]
    ax.plot(lim, lim, "k--", lw=1, label="nu C = tr F (eq. 20)")
    if slope is not None:
        ax.plot(lim, np.array(lim) / slope, "r:", lw=1, label=slope_label)
    ax.set_xlabel("tr F")
    ax.set_ylabel("nu C")
    ax.legend(fontsize=7)
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    save(fig, outdir, name, written)
    plt.close(fig)


def rve_figures(plt, e, products, outdir, written):
    """Figs. 5 and 6: each component of the members' mean strain and fabric at the RVE study's
    points against the number of grains in the RVE, with the paper's 100-200 and our choice."""
    rows = []
    with gzip.open(os.path.join(products, "rve_study.csv.gz"), "rt", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    points = sorted({int(r["point"]) for r in rows})
    chosen = e.report["coarse"]["rve_study"]["chosen_grain_count"]
    for name, kind, label in (("fig05_rve_strain", "strain", "strain"), ("fig06_rve_fabric", "fabric", "fabric")):
        fig, axes = plt.subplots(1, len(points), figsize=(4.2 * len(points), 3.6), squeeze=False)
        for ax, p in zip(axes[0], points):
            sel = [r for r in rows if int(r["point"]) == p]
            for comp, style in (("xx", "-"), ("yy", "--"), ("xy", ":")):
                d = np.array([(float(r["grain_count"]), float(r["value"])) for r in sel if r["quantity"] == f"{kind}_{comp}"])
                if len(d):
                    ax.plot(d[:, 0], d[:, 1], style, marker=".", ms=3, label=f"{label}_{comp}")
            ax.axvspan(100, 200, color="0.85", lw=0, label="paper: 100-200 grains")
            ax.axvline(chosen, color="r", lw=0.8, label=f"chosen: {chosen:.0f}")
            ax.set_xscale("log")
            ax.set_xlabel("grains in the RVE")
            ax.set_title(f"x = {float(sel[0]['x_m']):+.3f} m, y = {float(sel[0]['y_m']):.3f} m", fontsize=8)
        axes[0][0].set_ylabel(label)
        axes[0][0].legend(fontsize=6)
        fig.suptitle(f"{name.split('_', 1)[0].replace('fig0', 'Fig. ')}: RVE size, mean of {e.n} symmetric piles")
        fig.tight_layout()
        save(fig, outdir, name, written)
        plt.close(fig)


def figures(study, outdir):
    """One PNG per paper figure with data behind it (Figs. 5-9 and 11-17)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(outdir, exist_ok=True)
    written = []
    if "symmetric" in study:
        e, products, _, smooth_products = study["symmetric"]
        prof = read_profiles(products)
        smooth = read_profiles(smooth_products) if smooth_products else None
        cut_figures(plt, e, prof, smooth, {
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
        }, outdir, "symmetric", written)
        if os.path.exists(os.path.join(products, "rve_study.csv.gz")):
            rve_figures(plt, e, products, outdir, written)
        F = Fields(e, e.mean_fields(sorted(e.piles)))
        trace_figure(plt, e, outdir, "fig16b_fabric_trace", f"Fig. 16B: {e.n} polydisperse piles, points > 1 RVE radius deep",
                     g2_slope(F, e), "tr F = g2 nu C, g2 fitted", written)
        # Fig. 17: tr F against nu.
        tr, nu = F["fabric_xx"] + F["fabric_yy"], F["volume_fraction"]
        ok = np.isfinite(tr) & np.isfinite(nu) & e.interior()
        fig, ax = plt.subplots(figsize=(4.6, 4.2))
        ax.plot(nu[ok], tr[ok], ".", ms=2, color="0.3")
        k, c = np.polyfit(nu[ok], tr[ok], 1)
        xs = np.linspace(nu[ok].min(), nu[ok].max(), 2)
        ax.plot(xs, k * xs + c, "r-", lw=1, label=f"least squares: tr F = {k:.2f} nu {c:+.2f}")
        ax.set_xlabel("volume fraction nu")
        ax.set_ylabel("tr F")
        ax.legend(fontsize=7)
        ax.set_title(f"Fig. 17: {e.n} symmetric piles, points > 1 RVE radius deep", fontsize=9)
        fig.tight_layout()
        save(fig, outdir, "fig17_fabric_trace_volume_fraction", written)
        plt.close(fig)
    if "asymmetric" in study:
        e, products, _, smooth_products = study["asymmetric"]
        cut_figures(plt, e, read_profiles(products), read_profiles(smooth_products) if smooth_products else None,
                    {"fig11_asymmetric_stress": [("sigma_yy", "sigma_yy / rho g h")]}, outdir, "asymmetric", written)
    if "monodisperse" in study:
        e = study["monodisperse"][0]
        trace_figure(plt, e, outdir, "fig16a_fabric_trace_monodisperse",
                     f"Fig. 16A: {e.n} monodisperse piles, points > 1 RVE radius deep", None, "", written)
    return written


# --- The study ------------------------------------------------------------------------------

def load_study(root):
    """kind -> (ensemble, products, products of the RVE-study variant or None, of the smooth
    base or None), for every ensemble whose products exist under root."""
    study = {}
    for kind in ENSEMBLES:
        products = os.path.join(root, kind, "products")
        if not os.path.exists(os.path.join(products, "fields.h5")):
            continue
        optional = lambda name: (os.path.join(root, kind, name)  # noqa: E731
                                 if os.path.exists(os.path.join(root, kind, name, "report.json")) else None)
        study[kind] = (Ensemble(products, kind), products, optional("products_rve_study"), optional("products_smooth_base"))
    return study


def sections(study):
    out = []
    for kind, (e, _, rve_products, smooth_products) in study.items():
        rows = ENSEMBLES[kind][2](e)
        rows_rve, grains = None, "the RVE study's size"
        if rve_products and os.path.exists(os.path.join(rve_products, "fields.h5")):
            e_rve = Ensemble(rve_products, kind)
            rows_rve = ENSEMBLES[kind][2](e_rve)
            grains = f"{e_rve.report['coarse']['rve_study']['chosen_grain_count']:.0f} grains (the RVE study's choice)"
        smooth = None
        if smooth_products:
            with open(os.path.join(smooth_products, "report.json"), encoding="utf-8") as f:
                smooth = json.load(f)
        out.append((kind, e, with_rve_study_column(rows, rows_rve), comparison(e, smooth), grains))
    return out


def replace_between_markers(doc_path, script, text):
    """The doc with `text` between its markers "<!-- table: SCRIPT -->" and "<!-- end of
    table -->", written to a temporary name and renamed; exits naming the doc without them."""
    with open(doc_path, encoding="utf-8") as f:
        doc = f.read()
    begin, end = f"<!-- table: {script} -->\n", "<!-- end of table -->"
    if begin not in doc or end not in doc:
        sys.exit(f"{doc_path}: no table markers ({begin.strip()} ... {end})")
    doc = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda _: begin + text + end, doc, flags=re.S)
    with open(doc_path + ".tmp", "w", encoding="utf-8") as f:
        f.write(doc)
    os.replace(doc_path + ".tmp", doc_path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("root", nargs="?", default=os.path.join(ROOT, "docs", "studies", "paper"),
                        help="the study's folder, holding <ensemble>/products*/ (default docs/studies/paper)")
    parser.add_argument("--doc", default=os.path.join(ROOT, "docs", "studies", "paper.md"))
    parser.add_argument("--figures", help="where the PNGs go (default: the root)")
    args = parser.parse_args()
    study = load_study(args.root)
    if not study:
        sys.exit(f"tables.py: no products under {args.root}/<ensemble>/products (run studies/paper/stages.py)")
    table = markdown(sections(study))
    replace_between_markers(args.doc, "studies/paper/tables.py", table)
    print(f"tables.py: {len(table.splitlines())} lines of table -> {args.doc}")
    for path in figures(study, args.figures or args.root):
        print("tables.py: wrote", path)


if __name__ == "__main__":
    main()
