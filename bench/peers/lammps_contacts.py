#!/usr/bin/python3
"""Count the contacts in a LAMMPS data file of rounded polygons (as pile.in writes with -var write).

LAMMPS's write_data lists each body's vertices as displacements from its centre of mass in the
box frame (its current orientation) and its rounded diameter, so the file holds the whole
geometry. Two bodies touch when their rounded outlines overlap: the distance between the two
vertex polygons is at most the sum of their rounding radii, the condition under which
body/rounded/polygon pushes them apart (surface separation <= 0). A body touches the floor y = 0
when a vertex is less than its rounding radius above it (fix wall/body/polygon's test).

Prints the number of bodies, grain-grain contacts and floor contacts; touching pairs per body
(grain-grain and grain-floor pairs over the number of bodies, as pilelab's contacts_per_grain
counter counts them); the coordination number (contacts per body, each grain-grain contact
counted for both bodies, floor contacts once); and the share of bodies without any contact.
"""
import argparse
import sys

import numpy as np


def read_bodies(path):
    """Centres (N x 2), vertex lists (box frame, relative) and rounding radii, by atom ID."""
    with open(path) as f:
        lines = f.read().split("\n")
    centre = {}
    bodies = {}
    section = None
    i = 0
    n = len(lines)
    while i < n:
        raw = lines[i].split("#")[0].strip()
        i += 1
        if not raw:
            continue
        word = raw.split()[0]
        if word in ("Atoms", "Velocities", "Bodies", "Masses"):
            section = word
            continue
        if section == "Atoms":
            t = raw.split()
            if not t[0].lstrip("-").isdigit():
                section = None
                continue
            # atom-ID atom-type bodyflag mass x y z [image flags]
            centre[int(t[0])] = (float(t[4]), float(t[5]))
        elif section == "Bodies":
            t = raw.split()
            if len(t) != 3 or not t[0].isdigit():
                section = None
                continue
            atom, nint, nfloat = map(int, t)
            values = []
            while len(values) < nint + nfloat:
                values += lines[i].split()
                i += 1
            nv = int(values[0])
            floats = np.array(values[nint:], dtype=float)
            v = floats[6:6 + 3 * nv].reshape(nv, 3)[:, :2]
            bodies[atom] = (v, 0.5 * floats[6 + 3 * nv])
    ids = sorted(bodies)
    missing = [a for a in ids if a not in centre]
    if not ids or missing:
        sys.exit("%s: no Bodies section, or bodies without atoms" % path)
    return ids, np.array([centre[a] for a in ids]), [bodies[a][0] for a in ids], np.array([bodies[a][1] for a in ids])


def point_segment_distance(p, a, b):
    """Distances from the points p (.. x 2) to the segments a-b (.. x 2), broadcasting."""
    ab = b - a
    t = np.clip(((p - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
    d = p - (a + t[..., None] * ab)
    return np.hypot(d[..., 0], d[..., 1])


def polygon_distance(a, b):
    """Distance between two convex polygons (0 if they intersect)."""
    ea, eb = np.roll(a, -1, axis=0), np.roll(b, -1, axis=0)
    d = min(point_segment_distance(a[:, None, :], b[None, :, :], eb[None, :, :]).min(),
            point_segment_distance(b[:, None, :], a[None, :, :], ea[None, :, :]).min())
    # Intersecting polygons: a vertex of one inside the other (or crossing edges, which convex
    # polygons only have when a vertex of one lies inside the other).
    for p, q in ((a, b), (b, a)):
        e = np.roll(q, -1, axis=0) - q
        side = e[None, :, 0] * (p[:, None, 1] - q[None, :, 1]) - e[None, :, 1] * (p[:, None, 0] - q[None, :, 0])
        if np.any(np.all(side >= 0.0, axis=1)):
            return 0.0
    return d


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("data", help="data file written by LAMMPS (write_data) or make_lammps_pile.py")
    p.add_argument("--floor", type=float, default=0.0, help="height of the floor (default 0)")
    a = p.parse_args()
    ids, x, verts, rr = read_bodies(a.data)
    n = len(ids)
    world = [v + c for v, c in zip(verts, x)]
    reach = np.array([np.hypot(v[:, 0], v[:, 1]).max() for v in verts]) + rr
    # Candidate pairs from a grid of cells as wide as the largest body.
    cell = 2.0 * reach.max()
    key = np.floor(x / cell).astype(int)
    grid = {}
    for i, k in enumerate(map(tuple, key)):
        grid.setdefault(k, []).append(i)
    contacts = np.zeros(n, dtype=int)
    pairs = 0
    for i in range(n):
        kx, ky = key[i]
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for j in grid.get((kx + dx, ky + dy), ()):
                    if j <= i or np.hypot(*(x[i] - x[j])) > reach[i] + reach[j]:
                        continue
                    if polygon_distance(world[i], world[j]) <= rr[i] + rr[j]:
                        contacts[i] += 1
                        contacts[j] += 1
                        pairs += 1
    floor = np.array([int((w[:, 1] - a.floor < r).any()) for w, r in zip(world, rr)])
    total = contacts + floor
    print("%s: %d bodies, %d grain-grain and %d floor contacts: %.3f touching pairs per body, "
          "coordination %.3f contacts per body; %.1f %% of the bodies touch nothing"
          % (a.data, n, pairs, floor.sum(), (pairs + floor.sum()) / n, total.mean(),
             100.0 * (total == 0).mean()))


if __name__ == "__main__":
    main()
