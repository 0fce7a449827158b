#!/usr/bin/python3
"""Pours the arms of the signatures study's screen and keeps what its tables need
(docs/studies/signatures.md).

    /usr/bin/python3 studies/signatures/screen.py [--only ARM,...] [-P PROCESSES] [--out DIR] [--save]

An arm is a scene studies/signatures/<arm>.toml (an ensemble of paired seeds); its piles are
poured and taken through the later stages by studies/speed_accuracy/run.py (resumable: poured
members are kept, a checkpointed one continues), into OUT/<arm>. Then its compact products go to
docs/studies/signatures/data/<arm>/: base.json (run.py's measurements of the ensemble, with each
quantity's leave-one-out values for paired jackknife errors) and members.json (per pile: the
repose angles, height, lost grains, final kinetic energy, and the plate's load binned along
x' = (x - x_apex) / R with its dip statistic, computed here from dem.h5's settled contacts so
that piles of any build are measured alike). studies/signatures/tables.py needs only these.
--save keeps the members of arms begun but not measured in docs/studies/signatures/in_progress/
<arm> (commit it), from where the next run restores them.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DATA = os.path.join(ROOT, "docs", "studies", "signatures", "data")
IN_PROGRESS = os.path.join(ROOT, "docs", "studies", "signatures", "in_progress")
sys.path.insert(0, os.path.join(ROOT, "python"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import pilelab  # noqa: E402
import study_members  # noqa: E402

# The dip statistic of dem/plate_force.h: the centre |x'| < 0.1 over the ring 0.15 < |x'| < 0.35.
CENTRE, RING = 0.1, (0.15, 0.35)
# The plate's load is binned in x' so that members of different half-widths average bin by bin.
BINS = np.linspace(-1.5, 1.5, 61)


def arms():
    """Every scene of the study: the first screen's arms (studies/signatures/*.toml) and the cells
    of the second (studies/signatures/cells/*.toml, from design.py), named by their path without
    .toml."""
    scenes = glob.glob(os.path.join(HERE, "*.toml")) + glob.glob(os.path.join(HERE, "cells", "*.toml"))
    return sorted(os.path.splitext(os.path.relpath(p, HERE))[0] for p in scenes)


def centre_over_ring(x, load):
    u = np.abs(x)
    centre, ring = load[u < CENTRE], load[(u > RING[0]) & (u < RING[1])]
    if centre.size == 0 or ring.size == 0 or not ring.mean() > 0:
        return None
    return float(centre.mean() / ring.mean() - 1)


def member_products(directory):
    """One pile's compact numbers: from its report and its dem.h5's settled snapshot."""
    with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
        dem = json.load(f)["dem"]
    snap = pilelab.DemFile(os.path.join(directory, "dem.h5")).snapshot("settled")
    c = snap.contacts
    # The pile stands on the plate (body 0) and, with `base = "grains"`, on fixed grains. Walls
    # are laid in the order of dem/pile_protocol.cpp: the plate, the side walls if any, the
    # funnel's two plates if any, then the fixed grains of the base. A wall is the lower body
    # of its pairs.
    with open(os.path.join(directory, "scene.toml"), "rb") as f:
        scene = tomllib.load(f)["dem"]
    pour = scene.get("pour", {})
    side = 2 if scene.get("container", {}).get("side_walls", False) else 0
    funnel = 2 if pour.get("funnel_walls", pour.get("kind", "point_source") == "point_source") else 0
    walls = np.flatnonzero(snap.dem.bodies["is_wall"])
    base = np.concatenate([[0], walls[1 + side + funnel:]])
    on_plate = np.isin(c.pair[:, 0], base)
    x, down = c.point[on_plate, 0], c.force[on_plate, 1]
    weight = float(snap.gravity_m_per_s2 * np.sum(snap.dem.bodies["mass"][snap.body]))
    h, apex = dem["height_m"], dem["apex_x_m"]
    left, right = dem["repose_angle_left_deg"], dem["repose_angle_right_deg"]
    out = {"seed": dem["seed"], "repose_angle_left_deg": left, "repose_angle_right_deg": right,
           "height_m": h, "apex_x_m": apex, "lost": dem["lost"], "particles": dem["particles"],
           "kinetic_energy_final_J": dem["kinetic_energy_final_J"], "simulated_time_s": dem["simulated_time_s"],
           "cpu_time_s": dem.get("cpu_time_s"), "plate_force_over_weight": float(down.sum() / weight)}
    if left is None or right is None:
        out.update(half_width_m=None, plate_load_x_over_R=None, plate_load_over_weight_per_R=None, plate_force_dip=None)
        return out
    R = 0.5 * h * (1 / np.tan(np.radians(left)) + 1 / np.tan(np.radians(right)))
    xr = (x - apex) / R
    width = np.diff(BINS)
    # The load in each bin per unit length of x', over the weight: a profile that integrates to
    # the load over the weight and is compared across piles of any size.
    load = np.histogram(xr, BINS, weights=down)[0] / width / weight
    centres = 0.5 * (BINS[1:] + BINS[:-1])
    out.update(half_width_m=float(R), plate_load_x_over_R=[float(v) for v in centres],
               plate_load_over_weight_per_R=[float(v) for v in load], plate_force_dip=centre_over_ring(centres, load))
    return out


def keep(arm, out):
    """The arm's compact products, from its finished run in OUT/<arm>/base."""
    directory = os.path.join(out, arm, "base")
    with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
        report = json.load(f)
    members = [member_products(os.path.join(directory, m["directory"])) for m in report["ensemble"]["members"]]
    target = os.path.join(DATA, arm)
    os.makedirs(target, exist_ok=True)
    with open(os.path.join(target, "members.json.tmp"), "w", encoding="utf-8") as f:
        json.dump({"arm": arm, "members": members}, f, indent=1)
    os.replace(os.path.join(target, "members.json.tmp"), os.path.join(target, "members.json"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", help="comma-separated arms (default: every studies/signatures/*.toml)")
    parser.add_argument("-P", "--processes", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "signatures"))
    parser.add_argument("--save", action="store_true", help="keep the piles of arms begun but not measured, and stop")
    parser.add_argument("--pilelab", help="the binary (default: a copy of build/apps/pilelab in OUT, made once, "
                        "so that a rebuild during the screen cannot mix builds inside the study)")
    parser.add_argument("--extract-only", action="store_true", help="only write members.json of arms already run")
    args = parser.parse_args()
    chosen = args.only.split(",") if args.only else arms()
    if not args.pilelab:
        args.pilelab = os.path.join(args.out, "pilelab")
        if not os.path.exists(args.pilelab):
            os.makedirs(args.out, exist_ok=True)
            shutil.copy2(os.path.join(ROOT, "build", "apps", "pilelab"), args.pilelab + ".tmp")
            os.replace(args.pilelab + ".tmp", args.pilelab)
    unknown = set(chosen) - set(arms())
    if unknown:
        sys.exit(f"screen.py: --only: no arm {sorted(unknown)} (known: {arms()})")
    for arm in chosen:
        done = os.path.exists(os.path.join(DATA, arm, "members.json"))
        members = os.path.join(args.out, arm, "base", "members")
        if args.save:
            if not done and os.path.isdir(members):
                study_members.save(members, os.path.join(IN_PROGRESS, arm))
            continue
        if done:
            continue
        if not args.extract_only:
            if os.path.isdir(os.path.join(IN_PROGRESS, arm)) and not os.path.isdir(members):
                os.makedirs(members)
                study_members.restore(members, os.path.join(IN_PROGRESS, arm))
            env = dict(os.environ, OMP_WAIT_POLICY="passive", OMP_NUM_THREADS="1")
            subprocess.run([sys.executable, os.path.join(ROOT, "studies", "speed_accuracy", "run.py"), "--only", "base",
                            "-P", str(args.processes), "--pilelab", args.pilelab, "--base", os.path.join(HERE, arm + ".toml"),
                            "--data", os.path.join(DATA, arm), "--out", os.path.join(args.out, arm)], check=True, env=env)
        if os.path.exists(os.path.join(args.out, arm, "base", "report.json")):
            keep(arm, args.out)


if __name__ == "__main__":
    main()
