#!/usr/bin/python3
"""Runs the speed-accuracy study (docs/studies/speed_accuracy.md) and keeps what its table and
figure are computed from.

    /usr/bin/python3 studies/speed_accuracy/run.py [--only NAME,...] [-P PROCESSES] [--out DIR] [--base SCENE]

For every setting of settings.py: the base scene with the setting's overrides goes to
OUT/<name>/scene.toml, and `pilelab run` pours its ensemble (one member per process, -j 1) and
runs the later stages; the LATER settings rerun only the later stages on the base ensemble's
members (copied). Then the setting's measurements go to docs/studies/speed_accuracy/data/
<name>.json: every member's cost and angles, and every quantity of the ensemble with its
standard error (the jackknife over piles, as in the paper study). Resumable at both levels: a
setting whose data file exists is not run again (--force runs it), and `pilelab run` keeps the
members already poured. Across machines: after stopping a run, `run.py --save` keeps the piles
of the settings begun but not measured in docs/studies/speed_accuracy/in_progress/<name>
(commit it), from where the next run restores them. studies/speed_accuracy/tables.py needs
only the data files.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "studies", "paper"))
import settings as study  # noqa: E402
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import study_members  # noqa: E402  (save and restore of an ensemble's piles)
import stages  # noqa: E402  (the scene rewriting of the paper study)
import tables as paper  # noqa: E402  (its ensemble statistics)

DATA = os.path.join(ROOT, "docs", "studies", "speed_accuracy", "data")
# The piles of settings begun but not measured, kept across machines (scripts/study_members.py:
# poured piles archived, unfinished ones as checkpoints); a setting's folder goes once its data
# file is written.
IN_PROGRESS = os.path.join(ROOT, "docs", "studies", "speed_accuracy", "in_progress")


def scene_for(overrides, base_text):
    text = base_text
    for table, keys in overrides.items():
        for key, value in keys.items():
            text = stages.scene_with(text, table, key, value)
    return text


def write_atomically(path, text):
    with open(path + ".tmp", "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def run_setting(name, overrides, out, args, members_from=None):
    """Pours (or reuses) the ensemble and runs the later stages; returns the run directory."""
    with open(args.base, encoding="utf-8") as f:
        base = f.read()
    directory = os.path.join(out, name)
    os.makedirs(directory, exist_ok=True)
    scene = os.path.join(directory, "scene.toml")
    write_atomically(scene, scene_for(overrides, base))
    if members_from:  # later stages only: the base ensemble's members, as poured
        target = os.path.join(directory, "members")
        if not os.path.isdir(target):
            shutil.copytree(os.path.join(members_from, "members"), target)
    elif os.path.isdir(os.path.join(IN_PROGRESS, name)):  # begun on another machine
        os.makedirs(os.path.join(directory, "members"), exist_ok=True)
        study_members.restore(os.path.join(directory, "members"), os.path.join(IN_PROGRESS, name))
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    command = [args.pilelab, "run", scene, "-o", directory, "-P", str(args.processes), "-j", "1", "--no-figures", "-q"]
    # A study measures every pile it poured: a pile unfit for the later stages is recorded in the
    # report's status rather than stopping the study (a binary from before the status has no flag).
    if "--allow-unsettled" in subprocess.run([args.pilelab, "run", "--help"], capture_output=True, text=True).stdout:
        command.append("--allow-unsettled")
    subprocess.run(command, check=True, env=env)
    return directory


def measure(name, knob, value, directory):
    """What the table needs of one setting, as plain numbers with their standard errors."""
    with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
        report = json.load(f)
    members = []
    for m in report["ensemble"]["members"]:
        with open(os.path.join(directory, m["directory"], "report.json"), encoding="utf-8") as f:
            dem = json.load(f)["dem"]
        members.append({"seed": m["seed"], "wall_time_s": dem["wall_time_s"], "cpu_time_s": dem.get("cpu_time_s"),
                        "steps": dem["steps"],
                        "time_step_s": dem["time_step_s"], "stable_time_step_s": dem["stable_time_step_s"],
                        "particle_steps_per_s": dem["particle_steps_per_s"], "grains": m["grains"], "lost": m["lost"],
                        "height_m": m["height_m"], "repose_angle_left_deg": m["repose_angle_left_deg"],
                        "repose_angle_right_deg": m["repose_angle_right_deg"]})
    e = paper.Ensemble(directory, "symmetric")
    coarse = report["coarse"]
    rho_g_h = coarse["rho_bulk_kg_per_m2"] * coarse["gravity_m_per_s2"] * e.h
    quantities, leave_one_out = {}, {}

    def add(key, function):
        v, loo = e.replicates(function)
        quantities[key] = [float(v[0]), float(paper.jackknife_se(loo)[0])]
        leave_one_out[key] = [float(x) for x in loo[:, 0]]

    add("stress_tilt_flanks_deg", lambda F: F.mean(np.abs(F.axes("stress")[1]), e.flanks()))
    add("stress_anisotropy_core", lambda F: F.mean(F.axes("stress")[0], e.core()))
    add("fabric_trace_core", lambda F: F.mean(F["fabric_xx"] + F["fabric_yy"], e.core()))
    add("volume_fraction_core", lambda F: F.mean(F["volume_fraction"], e.core()))
    add("base_centre_over_max", paper.centre_over_max(0.0))
    x, loo = e.replicates(lambda F: tuple(F.profile(-F["stress_yy"], 0.0)[1] / rho_g_h))
    bins = np.linspace(-1, 1, 41)
    base_profile = {"x_over_R": list(0.5 * (bins[1:] + bins[:-1])), "value": [float(a) for a in x],
                    "stderr": [float(a) for a in paper.jackknife_se(loo)],
                    "leave_one_out": [[float(a) for a in row] for row in loo]}
    for model in ("elastic", "fpa"):
        m = report["compare"]["models"].get(model, {})
        for k in ("relative_l2_stress_yy", "relative_l2_stress_xx", "principal_axis_angle_mean_deg"):
            if m.get(k) is not None:
                quantities[f"{model}_{k}"] = [m[k], m.get(k + "_stderr")]
        wall = report["continuum"].get(model, {}).get("wall_time_s")
        if wall is not None:
            quantities[f"{model}_wall_time_s"] = [wall, None]
    fit = report.get("fit", {}).get("models", {}).get("isotropic", {})
    for k in ("E_N_per_m", "nu"):
        if fit.get(k) is not None and fit.get(k + "_ci95"):
            lo, hi = fit[k + "_ci95"]
            quantities[f"fit_{k}"] = [fit[k], (hi - lo) / 3.92]  # the 95 % interval as one SE
    ens = report["ensemble"]
    for side in ("left", "right", "pile_mean"):
        s = ens[f"repose_angle_{side}_deg"]
        quantities[f"repose_angle_{side}_deg"] = [s["mean"], s["standard_error"]]
    s = ens["height_m"]
    quantities["height_m"] = [s["mean"], s["standard_error"]]
    quantities["coarse_wall_time_s"] = [coarse.get("wall_time_s"), None]
    # The seeds in the order of the leave-one-out rows (fields.h5's piles follow the members).
    seeds = [m["seed"] for m in report["ensemble"]["members"]]
    return {"name": name, "knob": knob, "value": value, "members": members, "quantities": quantities,
            "leave_one_out": leave_one_out, "seeds": seeds,
            "base_profile": base_profile, "rve_grain_count": coarse.get("rve_grain_count_target"),
            "mesh_nodes": report.get("mesh", {}).get("nodes")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", help="comma-separated setting names (default: all)")
    parser.add_argument("-P", "--processes", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "speed_accuracy"))
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build", "apps", "pilelab"))
    parser.add_argument("--force", action="store_true", help="run settings whose data exist again")
    parser.add_argument("--data", default=DATA, help="where the measurements go (default docs/studies/speed_accuracy/data)")
    parser.add_argument("--base", default=os.path.join(HERE, "base.toml"), help="the base scene (default base.toml)")
    parser.add_argument("--save", action="store_true",
                        help="keep the piles of every setting begun but not measured in docs/studies/speed_accuracy/"
                             "in_progress (after stopping a run, before a change of machine), and stop")
    args = parser.parse_args()
    if args.save:
        save_in_progress(args)
        return
    only = set(args.only.split(",")) if args.only else None
    os.makedirs(args.data, exist_ok=True)
    # The base first, then what reuses its members (the later stages' settings), then the rest.
    plan = [(study.DEM[0], None)] + [(s, "base") for s in study.LATER] + [(s, None) for s in study.DEM[1:]]
    known = {s[0] for s, _ in plan} | {s[0] for s in study.SKIN}
    if only and only - known:
        sys.exit(f"run.py: --only: no setting {sorted(only - known)} (known: {sorted(known)})")
    for (name, knob, value, overrides), source in plan:
        if only and name not in only:
            continue
        data = os.path.join(args.data, name + ".json")
        if os.path.exists(data) and not args.force:
            print(f"run.py: {name}: measured already ({data})", flush=True)
            continue
        print(f"run.py: {name} ({knob} = {value})", flush=True)
        members_from = os.path.join(args.out, source) if source else None
        if members_from and not os.path.isdir(os.path.join(members_from, "members")):
            run_setting(source, {}, args.out, args)
        directory = run_setting(name, overrides, args.out, args, members_from)
        write_atomically(data, json.dumps(measure(name, knob, value, directory), indent=1) + "\n")
        shutil.rmtree(os.path.join(IN_PROGRESS, name), ignore_errors=True)
    for name, knob, value, overrides in study.SKIN:  # last: each pours one pile
        if only and name not in only:
            continue
        data = os.path.join(args.data, name + ".json")
        if os.path.exists(data) and not args.force:
            continue
        skin_run(name, knob, value, overrides, args, data)


def save_in_progress(args):
    """Every DEM setting with piles in OUT but no data file: its piles into IN_PROGRESS; and
    the piles kept there of settings measured since, removed."""
    later = {s[0] for s in study.LATER}
    if os.path.isdir(IN_PROGRESS):
        for name in os.listdir(IN_PROGRESS):
            if os.path.exists(os.path.join(args.data, name + ".json")):
                shutil.rmtree(os.path.join(IN_PROGRESS, name))
    for name, *_ in study.DEM:
        members = os.path.join(args.out, name, "members")
        if name in later or os.path.exists(os.path.join(args.data, name + ".json")) or not os.path.isdir(members):
            continue
        study_members.save(members, os.path.join(IN_PROGRESS, name))


def skin_run(name, knob, value, overrides, args, data):
    """One pile (base.toml's [dem].seed) poured by `pilelab dem` with another skin: its grains
    must end where the default skin's do, exactly; its cost is what the skin changes."""
    import h5py
    with open(args.base, encoding="utf-8") as f:
        text = scene_for(overrides, f.read())
    directory = os.path.join(args.out, name)
    os.makedirs(directory, exist_ok=True)
    scene = os.path.join(directory, "scene.toml")
    write_atomically(scene, text)
    subprocess.run([args.pilelab, "dem", scene, "-o", directory, "-j", "1", "-q"], check=True,
                   env=dict(os.environ, OMP_WAIT_POLICY="passive"))
    with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
        dem = json.load(f)["dem"]
    result = {"name": name, "knob": knob, "value": value, "wall_time_s": dem["wall_time_s"],
              "cpu_time_s": dem.get("cpu_time_s"), "steps": dem["steps"],
              "neighbour_list_builds": dem.get("neighbour_list_builds"),
              "particle_steps_per_s": dem["particle_steps_per_s"]}
    reference = os.path.join(args.out, study.SKIN[0][0], "dem.h5")
    mine = os.path.join(directory, "dem.h5")
    if os.path.abspath(reference) != os.path.abspath(mine):
        with h5py.File(reference, "r") as a, h5py.File(mine, "r") as b:
            same = all(np.array_equal(a[f"snapshots/{s}/position"][()], b[f"snapshots/{s}/position"][()])
                       for s in a["snapshots"])
        result["same_grain_positions_as_default_skin"] = bool(same)
    write_atomically(data, json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
