#!/usr/bin/python3
"""Write a LAMMPS data file of a 2D heap of rounded convex polygons (atom_style body rounded/polygon).

The grains are drawn like pilelab's paper grains (dem/grain_generator.cpp): 6 to 8 corners at
angles 2 pi (k + xi_k) / n, xi_k uniform in [-0.25, 0.25], on an ellipse whose two axes are each
drawn uniformly from 6.8 mm * [0.7, 1.3]; each grain gets a uniformly random orientation. Mass is
the areal density (5000 kg/m^2) times the polygon's area, the moment of inertia that of the
polygon about its centroid.

LAMMPS rounds every vertex by a disc of radius r (the last float of a body's entry is the
rounded *diameter* 2 r; LAMMPS itself computes the enclosing radius, the largest distance of a
vertex from the centre of mass, and sets the atom radius to enclosing + rounded radius). So that
the rounded body has the sharp polygon's edges, the vertices written are those of the polygon
offset inwards by r: the body's outline is the sharp grain with its corners rounded off (radius
r), its edges on the sharp grain's edges. Mass and inertia are the sharp polygon's.

The grains form a heap on the floor y = 0 with the row counts of pilelab's own synthetic pile
(bench/pile_step_bench.cpp): row k (k = 0, 1, ...) holds 2 (C - k) + 1 grains, C = 110, until all
are placed (the last row centred). Each row is set side by side, --gap apart, centred on x = 0,
and each grain is lowered vertically until it rests, --gap clear, on the floor or on the grains
placed before it. So the heap starts nearly dense, without overlaps (checked for every pair),
and packs under gravity within milliseconds. (A lattice of pilelab's 8.2 mm would start some
grains inside each other, and a wider one would first have to collapse.)

Units: LAMMPS 'units lj' read as millimetre, gram, millisecond, so that force is in N, stiffness
in N/mm, damping in N s/m, mass in g and the areal density 5000 kg/m^2 is 5 g/mm^2 (pile.in says
why: the body styles use absolute tolerances of 1e-3 length units).

Everything follows from --seed: the same arguments write the same file.
"""
import argparse
import math
import sys

import numpy as np

MEAN_DIAMETER_MM = 6.8
POLYDISPERSITY = 0.3
CORNERS_MIN, CORNERS_MAX = 6, 8
CORNER_JITTER = 0.25
AREAL_DENSITY = 5.0  # g/mm^2 = 5000 kg/m^2


def random_polygon(rng):
    """Corners (n x 2, counter-clockwise, mm) of one grain in its own frame."""
    lo = MEAN_DIAMETER_MM * (1.0 - POLYDISPERSITY)
    hi = MEAN_DIAMETER_MM * (1.0 + POLYDISPERSITY)
    a = 0.5 * rng.uniform(lo, hi)
    b = 0.5 * rng.uniform(lo, hi)
    n = int(rng.integers(CORNERS_MIN, CORNERS_MAX + 1))
    phi = 2.0 * math.pi * (np.arange(n) + rng.uniform(-CORNER_JITTER, CORNER_JITTER, n)) / n
    return np.column_stack((a * np.cos(phi), b * np.sin(phi)))


def moments(v):
    """Area, centroid and the second moments about the centroid (int x^2, int y^2, int xy) of a
    counter-clockwise polygon v (n x 2)."""
    x, y = v[:, 0], v[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    c = x * yn - xn * y
    area = 0.5 * c.sum()
    cx = ((x + xn) * c).sum() / (6.0 * area)
    cy = ((y + yn) * c).sum() / (6.0 * area)
    # Second moments about the centroid: shift first, then the shoelace sums.
    x, y, xn, yn = x - cx, y - cy, xn - cx, yn - cy
    c = x * yn - xn * y
    sxx = ((x * x + x * xn + xn * xn) * c).sum() / 12.0
    syy = ((y * y + y * yn + yn * yn) * c).sum() / 12.0
    sxy = ((x * yn + 2.0 * x * y + 2.0 * xn * yn + xn * y) * c).sum() / 24.0
    return area, np.array([cx, cy]), sxx, syy, sxy


def offset_inwards(v, r):
    """The convex polygon whose Minkowski sum with a disc of radius r has v's edges: every edge
    line moved inwards by r, the new corners where neighbouring lines cross."""
    n = len(v)
    e = np.roll(v, -1, axis=0) - v  # edge k runs from v[k] to v[k+1]
    length = np.hypot(e[:, 0], e[:, 1])
    t = e / length[:, None]
    normal = np.column_stack((t[:, 1], -t[:, 0]))  # outward for a counter-clockwise polygon
    p = v - r * normal  # a point on each shifted line
    out = np.empty_like(v)
    for k in range(n):
        j = k - 1  # corner k joins edge k-1 and edge k
        # p[j] + s t[j] = p[k] + u t[k]
        m = np.array([[t[j, 0], -t[k, 0]], [t[j, 1], -t[k, 1]]])
        s, _ = np.linalg.solve(m, p[k] - p[j])
        out[k] = p[j] + s * t[j]
    # Valid only if every edge keeps its direction (no edge shorter than the rounding eats).
    e2 = np.roll(out, -1, axis=0) - out
    if np.any((e2 * e).sum(axis=1) <= 0.0):
        raise ValueError("rounding radius %g mm removes an edge of a grain; choose a smaller --rounding" % r)
    return out


def x_range(v):
    return v[:, 0].min(), v[:, 0].max()


def boundary_heights(poly, xs, upper):
    """Height of the upper (or lower) boundary of the convex polygons poly (K x n x 2, padded by
    repeating the last corner) at the abscissae xs (K x m); NaN where xs is outside a polygon."""
    a = poly
    b = np.roll(poly, -1, axis=1)
    dxe = b[:, :, 0] - a[:, :, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (xs[:, :, None] - a[:, None, :, 0]) / dxe[:, None, :]
        y = a[:, None, :, 1] + t * (b[:, None, :, 1] - a[:, None, :, 1])
    ok = (t >= 0.0) & (t <= 1.0) & (dxe[:, None, :] != 0.0)
    if upper:
        return np.where(ok, y, -np.inf).max(axis=2)
    return np.where(ok, y, np.inf).min(axis=2)


def pad(v, n=CORNERS_MAX):
    return np.vstack((v, np.repeat(v[-1:], n - len(v), axis=0)))


def drop_height(v, x, placed, ranges, gap):
    """The lowest centroid height at which the sharp polygon v (corners relative to its centroid),
    centred at abscissa x and lowered vertically, clears the floor y = 0 and every placed polygon
    (absolute corners, K x 8 x 2) by gap."""
    lo, hi = x_range(v)
    y = -v[:, 1].min() + gap
    if len(ranges) == 0:
        return y
    near = np.nonzero((ranges[:, 1] > x + lo) & (ranges[:, 0] < x + hi))[0]
    if len(near) == 0:
        return y
    q = placed[near]  # K x 8 x 2
    k = len(near)
    # Corners of v landing on the top of q: centroid height = top of q - corner's y.
    px = np.broadcast_to(x + v[:, 0], (k, len(v)))
    top = boundary_heights(q, px, upper=True) - v[None, :, 1]
    # Corners of q touching the underside of v: centroid height = corner's y - underside of v.
    vp = np.broadcast_to(pad(v)[None], (k, CORNERS_MAX, 2))
    under = boundary_heights(vp, q[:, :, 0] - x, upper=False)
    bottom = q[:, :, 1] - under
    best = max(np.max(top, initial=-np.inf), np.max(np.where(np.isfinite(bottom), bottom, -np.inf), initial=-np.inf))
    return max(y, best + gap)


def build(n_grains, seed, rounding, half_columns, gap):
    """The grains of a heap: row k holds 2 (C - k) + 1 grains side by side (the last row fewer),
    each row centred on x = 0, every grain lowered from above until it rests on the floor or on
    the grains already placed (sharp polygons, gap apart)."""
    rng = np.random.default_rng(seed)
    grains = []
    placed = np.empty((n_grains, CORNERS_MAX, 2))
    ranges = np.empty((n_grains, 2))
    row = 0
    while len(grains) < n_grains:
        count = min(2 * (half_columns - row) + 1, n_grains - len(grains))
        if count <= 0:
            raise ValueError("the heap's %d rows hold fewer than %d grains; raise --half-columns" % (row, n_grains))
        # Draw the row's grains, then set them side by side, gap apart, centred on x = 0.
        shapes = []
        for _ in range(count):
            v = random_polygon(rng)
            theta = rng.uniform(0.0, 2.0 * math.pi)
            c, s = math.cos(theta), math.sin(theta)
            v = v @ np.array([[c, s], [-s, c]])  # rotate every corner by theta (stays counter-clockwise)
            area, centroid, sxx, syy, sxy = moments(v)
            shapes.append((v - centroid, area, sxx, syy, sxy))
        xs = []
        right = 0.0
        for v, *_ in shapes:
            lo, hi = x_range(v)
            xs.append(right - lo if xs else 0.0)
            right = xs[-1] + hi + gap
        first_lo = x_range(shapes[0][0])[0]
        last_hi = x_range(shapes[-1][0])[1]
        shift = -0.5 * (xs[0] + first_lo + xs[-1] + last_hi)
        for (v, area, sxx, syy, sxy), x in zip(shapes, xs):
            x += shift
            m = len(grains)
            y = drop_height(v, x, placed[:m], ranges[:m], gap)
            placed[m] = pad(v) + (x, y)
            ranges[m] = (x + v[:, 0].min(), x + v[:, 0].max())
            mass = AREAL_DENSITY * area
            # Inertia tensor about the centre of mass in the box frame (LAMMPS diagonalises it):
            # Ixx = rho int y^2, Iyy = rho int x^2, Izz = Ixx + Iyy, Ixy = -rho int xy.
            inertia = (AREAL_DENSITY * syy, AREAL_DENSITY * sxx, AREAL_DENSITY * (sxx + syy),
                       -AREAL_DENSITY * sxy, 0.0, 0.0)
            grains.append(dict(x=x, y=y, mass=mass, area=area, inertia=inertia,
                               vertices=offset_inwards(v, rounding), sharp=v))
        row += 1
    return grains, row


def write(path, grains, rounding, box, seed):
    xlo, xhi, ylo, yhi, zlo, zhi = box
    with open(path, "w") as f:
        f.write("LAMMPS data file: %d rounded polygons (pilelab peer benchmark, seed %d, "
                "units mm g ms)\n\n" % (len(grains), seed))
        f.write("%d atoms\n%d bodies\n1 atom types\n\n" % (len(grains), len(grains)))
        f.write("%.6f %.6f xlo xhi\n%.6f %.6f ylo yhi\n%.6f %.6f zlo zhi\n\n" % box)
        f.write("Atoms # body\n\n")  # atom-ID atom-type bodyflag mass x y z
        for i, g in enumerate(grains, 1):
            f.write("%d 1 1 %.12g %.12g %.12g 0\n" % (i, g["mass"], g["x"], g["y"]))
        f.write("\nBodies\n\n")
        for i, g in enumerate(grains, 1):
            v = g["vertices"]
            # atom-ID, number of integers (1), number of floats (6 + 3 N + 1)
            f.write("%d 1 %d\n%d\n" % (i, 6 + 3 * len(v) + 1, len(v)))
            f.write(" ".join("%.12g" % q for q in g["inertia"]) + "\n")
            for px, py in v:
                f.write("%.12g %.12g 0\n" % (px, py))
            f.write("%.12g\n" % (2.0 * rounding))


def time_step_bound(grains, rounding, kn, mu, cn):
    """The largest stable step [ms] on the stiffest contact a grain can form with its twin, as
    pilelab bounds its own step (dem/time_step.cpp), for LAMMPS's contact: a vertex on an edge,
    stiffness (1 + mu) kn (this version of body/rounded/polygon adds mu times the elastic force
    along the normal), damping cn, the force perpendicular to the lever from the centre of mass
    to the contact point, at most the body's enclosing radius. Two twins move the effective mass
    1 / (2 (1/m + a^2/I)); nve/body is velocity Verlet, whose forces see the half-step velocity,
    so the damped limit is leapfrog's, 2 (sqrt(1 + zeta^2) - zeta) / omega. Returns the bound and
    the undamped one, each the smallest over the grains."""
    best = (math.inf, math.inf)
    k = (1.0 + mu) * kn
    for g in grains:
        lever = np.hypot(g["vertices"][:, 0], g["vertices"][:, 1]).max() + rounding
        inv_mass = 2.0 * (1.0 / g["mass"] + lever * lever / g["inertia"][2])
        omega = math.sqrt(k * inv_mass)
        zeta = 0.5 * cn * math.sqrt(inv_mass / k)
        best = (min(best[0], 2.0 * (math.sqrt(1.0 + zeta * zeta) - zeta) / omega), min(best[1], 2.0 / omega))
    return best


def overlapping_pairs(grains):
    """Pairs of overlapping sharp polygons (separating-axis test on every pair whose bounding
    boxes overlap); the placement should leave none. (The rounded bodies lie inside the sharp
    polygons, so they do not overlap either.)"""
    boxes = np.array([[g["x"] + g["sharp"][:, 0].min(), g["x"] + g["sharp"][:, 0].max(),
                       g["y"] + g["sharp"][:, 1].min(), g["y"] + g["sharp"][:, 1].max()] for g in grains])
    bad = []
    tol = 0.0
    for i, g in enumerate(grains):
        near = np.nonzero((boxes[:, 0] < boxes[i, 1] + tol) & (boxes[:, 1] > boxes[i, 0] - tol) &
                          (boxes[:, 2] < boxes[i, 3] + tol) & (boxes[:, 3] > boxes[i, 2] - tol))[0]
        a = g["sharp"] + (g["x"], g["y"])
        for j in near[near > i]:
            b = grains[j]["sharp"] + (grains[j]["x"], grains[j]["y"])
            separated = False
            for p in (a, b):
                e = np.roll(p, -1, axis=0) - p
                axes = np.column_stack((e[:, 1], -e[:, 0])) / np.hypot(e[:, 0], e[:, 1])[:, None]
                pa, pb = a @ axes.T, b @ axes.T
                if np.any((pa.min(axis=0) > pb.max(axis=0) + tol) | (pb.min(axis=0) > pa.max(axis=0) + tol)):
                    separated = True
                    break
            if not separated:
                bad.append((i, int(j)))
    return bad


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("-o", "--out", default="pile.data", help="data file to write (default pile.data)")
    p.add_argument("--grains", type=int, default=6500, help="number of bodies (default 6500, as pile_step_bench)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--rounding", type=float, default=0.1, help="rounding radius r [mm] (default 0.1)")
    p.add_argument("--gap", type=float, default=0.02,
                   help="clearance between neighbouring sharp polygons and to the floor [mm] (default 0.02)")
    p.add_argument("--half-columns", type=int, default=110,
                   help="the bottom row holds 2 C + 1 grains, each row above one fewer on either side (default 110)")
    p.add_argument("--box", type=float, nargs=4, default=[-1500.0, 1500.0, -5.0, 600.0],
                   metavar=("XLO", "XHI", "YLO", "YHI"), help="box [mm] (default -1500 1500 -5 600)")
    p.add_argument("--no-check", action="store_true", help="skip the final check that no two grains overlap")
    p.add_argument("--kn", type=float, default=1.0e4, help="for the time-step bound only: pile.in's kn [N/mm]")
    p.add_argument("--mu", type=float, default=0.54, help="for the time-step bound only: pile.in's mu")
    p.add_argument("--cn", type=float, default=670.0, help="for the time-step bound only: pile.in's cn [N s/m]")
    a = p.parse_args()
    grains, rows = build(a.grains, a.seed, a.rounding, a.half_columns, a.gap)
    if not a.no_check:
        bad = overlapping_pairs(grains)
        if bad:
            sys.exit("placement bug: %d overlapping pairs, e.g. %s" % (len(bad), bad[:5]))
    xs = np.array([g["x"] for g in grains])
    ys = np.array([g["y"] for g in grains])
    largest = max(np.hypot(g["sharp"][:, 0], g["sharp"][:, 1]).max() for g in grains)
    if xs.min() - largest < a.box[0] or xs.max() + largest > a.box[1] or ys.max() + largest > a.box[3]:
        sys.exit("the heap does not fit in the box")
    write(a.out, grains, a.rounding, (a.box[0], a.box[1], a.box[2], a.box[3], -0.5, 0.5), a.seed)
    masses = np.array([g["mass"] for g in grains])
    corners = np.array([len(g["vertices"]) for g in grains])
    area = sum(g["area"] for g in grains)
    print("%s: %d bodies in %d rows, x %.1f .. %.1f mm, highest centre at y = %.1f mm; mass %.1f .. %.1f g "
          "(mean %.1f, total %.3f kg), corners %d .. %d (mean %.2f), largest corner radius %.3f mm, "
          "rounding %.3f mm, grain area %.4f m^2"
          % (a.out, len(grains), rows, xs.min(), xs.max(), ys.max(), masses.min(), masses.max(),
             masses.mean(), masses.sum() / 1000.0, corners.min(), corners.max(), corners.mean(),
             largest, a.rounding, area * 1e-6))
    damped, undamped = time_step_bound(grains, a.rounding, a.kn, a.mu, a.cn)
    print("time-step bound for kn %g N/mm, mu %g, cn %g N s/m (twin grains, a vertex at the largest lever): "
          "%.4f ms damped, %.4f ms undamped" % (a.kn, a.mu, a.cn, damped, undamped))


if __name__ == "__main__":
    main()
