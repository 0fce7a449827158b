#!/usr/bin/python3
"""The FPA's base pressure on a DEM outline, with and without its characteristics as mesh edges.

On a wedge the FPA stress is exact once the two rays from the apex are mesh edges; where they
cut through cells the least-squares solution smears each kink over several cells either side of
the ray's foot (docs/CONTINUUM.md, Limitations). A DEM outline has no exact solution, so this
measures against the finest mesh with the rays embedded: for each element size, with and without
the rays, the base sigma_yy's RMS and largest difference from that reference (in rho g h), and
the largest within five cells of a ray's foot and elsewhere.

Usage: studies/extremes/fpa_rays_on_dem_outline.py [--pilelab build/apps/pilelab]
           [--dem docs/studies/paper/symmetric/data/1/dem.h5] [--out out/fpa_rays]
Writes docs/studies/extremes/fpa_rays_on_dem_outline.csv and prints the table.
"""
import argparse
import csv
import json
import math
import os
import subprocess

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIZES_M = [0.02, 0.01, 0.005]
REFERENCE_SIZE_M = 0.0025
DENSITY, GRAVITY = 1000.0, 9.81  # the FPA's stress is linear in rho g: any values do


def scene_text(dem_file, size, rays, left, right):
    return f"""[mesh]
kind = "dem_outline"
dem_file = "{dem_file}"
element_size_m = {size}
embed_fpa_rays = {"true" if rays else "false"}
left_angle_deg = {left}
right_angle_deg = {right}

[continuum]
models = ["fpa"]
density_kg_per_m2 = {DENSITY}
gravity_m_per_s2 = {GRAVITY}

[continuum.fpa]
left_repose_angle_deg = {left}
right_repose_angle_deg = {right}
"""


def solve(pilelab, dem_file, out, size, rays, left, right):
    """Meshes and solves once (kept if done); returns the base nodes' x and sigma_yy, and the mesh section."""
    directory = os.path.join(out, f"{size:g}_{'rays' if rays else 'axis'}")
    done = os.path.join(directory, "models.h5")
    if not os.path.exists(done):
        os.makedirs(directory, exist_ok=True)
        scene = os.path.join(directory, "scene.toml")
        with open(scene, "w") as f:
            f.write(scene_text(dem_file, size, rays, left, right))
        for command in ("mesh", "solve"):
            subprocess.run([pilelab, command, scene, "-o", directory], check=True)
    report = json.load(open(os.path.join(directory, "report.json")))
    with h5py.File(done) as f:
        points = f["fpa/points"][:]
        syy = f["fpa/stress_yy"][:]
    on_base = np.abs(points[:, 1]) < 1e-12
    order = np.argsort(points[on_base, 0])
    return points[on_base, 0][order], -syy[on_base][order], report["mesh"], report["continuum"]["fpa"]


def largest_near_and_away(x, error, feet, size, cells=5):
    """The largest difference within `cells` elements of a ray's foot, and elsewhere."""
    near = np.zeros_like(x, dtype=bool)
    for foot in feet:
        near |= np.abs(x - foot) <= cells * size
    away = ~near
    return (float(np.max(np.abs(error[near]))) if near.any() else 0.0,
            float(np.max(np.abs(error[away]))) if away.any() else 0.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build/apps/pilelab"))
    parser.add_argument("--dem", default=os.path.join(ROOT, "docs/studies/paper/symmetric/data/1/dem.h5"))
    parser.add_argument("--out", default=os.path.join(ROOT, "out/fpa_rays"))
    args = parser.parse_args()
    dem_report = json.load(open(os.path.join(os.path.dirname(args.dem), "report.json")))["dem"]
    left, right = dem_report["repose_angle_left_deg"], dem_report["repose_angle_right_deg"]

    x_ref, s_ref, mesh_ref, _ = solve(args.pilelab, args.dem, args.out, REFERENCE_SIZE_M, True, left, right)
    if not mesh_ref.get("fpa_rays_embedded"):
        raise SystemExit("the reference mesh could not embed the rays: " + mesh_ref.get("fpa_rays_not_embedded_because", "?"))
    height = mesh_ref["height_m"]
    scale = DENSITY * GRAVITY * height
    # The apex: the outline's highest point, which the axis runs down from (a base node).
    with h5py.File(os.path.join(args.out, f"{REFERENCE_SIZE_M:g}_rays", "models.h5")) as f:
        points = f["fpa/points"][:]
    apex_x = points[np.argmax(points[:, 1]), 0]
    feet = {"left": apex_x - height * math.tan(math.radians(45 - left / 2)),
            "right": apex_x + height * math.tan(math.radians(45 - right / 2))}

    rows = []
    for size in SIZES_M:
        for rays in (False, True):
            x, s, mesh, fpa = solve(args.pilelab, args.dem, args.out, size, rays, left, right)
            # The difference at the reference's base nodes (the coarse solution is linear between its nodes).
            inside = (x_ref >= x[0]) & (x_ref <= x[-1])
            error = (np.interp(x_ref[inside], x, s) - s_ref[inside]) / scale
            xs = x_ref[inside]
            near, away = largest_near_and_away(xs, error, feet.values(), size)
            rows.append({
                "element_size_m": size,
                "rays_embedded": bool(mesh.get("fpa_rays_embedded", False)),
                "triangles": mesh["triangles"],
                "base_rms_error_rho_g_h": float(np.sqrt(np.trapz(error ** 2, xs) / (xs[-1] - xs[0]))),
                "base_max_error_rho_g_h": float(np.max(np.abs(error))),
                "base_max_error_near_ray_feet_rho_g_h": near,
                "base_max_error_elsewhere_rho_g_h": away,
                "base_force_over_weight": fpa["base_force_over_weight"],
            })
    target = os.path.join(ROOT, "docs/studies/extremes/fpa_rays_on_dem_outline.csv")
    os.makedirs(os.path.dirname(target), exist_ok=True)
    with open(target + ".tmp", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(target + ".tmp", target)
    print(f"DEM outline of {args.dem} (h = {height:.3f} m, phi = {left:.2f} / {right:.2f} deg); "
          f"reference: {REFERENCE_SIZE_M} m elements with the rays embedded ({mesh_ref['triangles']} triangles)")
    print("| element size (m) | rays | triangles | base RMS difference (rho g h) | largest | largest within 5 cells of a ray's foot / elsewhere | base force / weight |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['element_size_m']} | {'embedded' if r['rays_embedded'] else 'cut through cells'} | {r['triangles']} | "
              f"{r['base_rms_error_rho_g_h']:.4f} | {r['base_max_error_rho_g_h']:.4f} | "
              f"{r['base_max_error_near_ray_feet_rho_g_h']:.4f} / {r['base_max_error_elsewhere_rho_g_h']:.4f} | {r['base_force_over_weight']:.4f} |")


if __name__ == "__main__":
    main()
