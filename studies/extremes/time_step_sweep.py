#!/usr/bin/python3
"""The 40-grain test pile poured at multiples of the stability bound, an ensemble of seeds each.

For each scheme and factor, every seed's pile (tests/cli/tiny.toml with that seed) is poured at
that multiple of its own bound (the limit `pilelab check` names when it refuses a step far above
it), with allow_unstable_time_step. Per setting: how many runs stopped and by which check, and
of those that completed the lost grains and the kinetic energy per grain at the `settled`
snapshot (mean and standard error), the longest swing of a contact (World::longest_swing) and
the deepest overlap as a fraction of the inner radius (docs/DEM.md, "Protocol").

Usage: studies/extremes/time_step_sweep.py [--pilelab build/apps/pilelab] [--seeds 16]
           [--out out/time_step_sweep]
Writes docs/studies/extremes/time_step_sweep.csv and prints the table. One core, about 6 minutes.
"""
import argparse
import csv
import json
import math
import os
import re
import statistics
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCHEMES = ["verlet", "leapfrog", "gear5"]
FACTORS = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 10.0]
# What each check's message says, as PileProtocol and World write it.
CAUSES = {"period of two time steps": "swing", "creates energy": "energy", "no longer finite": "finite"}


def scene(base, scheme, seed, step_lines):
    text = base.replace('scheme = "verlet"', f'scheme = "{scheme}"\n{step_lines}')
    return re.sub(r"^seed = .*$", f"seed = {seed}", text, flags=re.M)


def bound(pilelab, base, scheme, seed, work):
    path = os.path.join(work, f"bound_{scheme}_{seed}.toml")
    with open(path, "w") as f:
        f.write(scene(base, scheme, seed, "time_step_s = 1.0"))
    out = subprocess.run([pilelab, "check", path], capture_output=True, text=True)
    found = re.search(r"exceeds the stability limit ([0-9.eE+-]+) s", out.stdout + out.stderr)
    if not found:
        raise SystemExit(f"time_step_sweep: `pilelab check {path}` named no stability limit")
    return float(found.group(1))


def mean_and_error(values):
    if not values:
        return math.nan, math.nan
    if len(values) == 1:
        return values[0], math.nan
    return statistics.mean(values), statistics.stdev(values) / math.sqrt(len(values))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build/apps/pilelab"))
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--out", default=os.path.join(ROOT, "out/time_step_sweep"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(ROOT, "tests/cli/tiny.toml")) as f:
        base = f.read()
    rows = []
    for scheme in SCHEMES:
        limits = {seed: bound(args.pilelab, base, scheme, seed, args.out) for seed in range(1, args.seeds + 1)}
        for factor in FACTORS:
            stops = {cause: 0 for cause in CAUSES.values()}
            lost, energy, swing, deepest = [], [], [], []
            for seed, limit in limits.items():
                name = f"{scheme}_x{factor:g}_seed{seed}"
                path = os.path.join(args.out, name + ".toml")
                with open(path, "w") as f:
                    f.write(scene(base, scheme, seed,
                                  f"time_step_s = {factor * limit:.9e}\nallow_unstable_time_step = true"))
                run = subprocess.run([args.pilelab, "dem", path, "-o", os.path.join(args.out, name), "-q", "-j", "1"],
                                     capture_output=True, text=True)
                if run.returncode != 0:
                    cause = next((c for text, c in CAUSES.items() if text in run.stderr), None)
                    if run.returncode != 1 or cause is None:
                        raise SystemExit(f"time_step_sweep: {name} failed without a check's message: {run.stderr}")
                    stops[cause] += 1
                    continue
                with open(os.path.join(args.out, name, "report.json")) as f:
                    dem = json.load(f)["dem"]
                lost.append(dem["lost"])
                energy.append(dem["settling"]["settled"]["kinetic_energy_per_grain_J"])
                swing.append(dem["longest_swing_steps"])
                deepest.append(dem["deepest_overlap_fraction"])
            lost_mean, lost_error = mean_and_error(lost)
            energy_mean, energy_error = mean_and_error(energy)
            rows.append({
                "scheme": scheme, "factor_of_bound": factor, "seeds": args.seeds, "completed": len(lost),
                "stopped_by_swing": stops["swing"], "stopped_by_energy": stops["energy"],
                "stopped_not_finite": stops["finite"],
                "lost_mean": lost_mean, "lost_se": lost_error,
                "kinetic_energy_per_grain_settled_J_mean": energy_mean,
                "kinetic_energy_per_grain_settled_J_se": energy_error,
                "longest_swing_steps_max": max(swing) if swing else "",
                "deepest_overlap_fraction_max": max(deepest) if deepest else "",
            })
            r = rows[-1]
            print(f"{scheme:8s} x{factor:<4g} completed {r['completed']:2d}/{args.seeds} "
                  f"(stopped: swing {stops['swing']}, energy {stops['energy']}, finite {stops['finite']})  "
                  f"lost {lost_mean:.2f} +- {lost_error:.2f}  KE {energy_mean:.2e} +- {energy_error:.2e} J  "
                  f"swing max {r['longest_swing_steps_max']}  deepest {r['deepest_overlap_fraction_max']}", flush=True)
    target = os.path.join(ROOT, "docs/studies/extremes/time_step_sweep.csv")
    with open(target + ".tmp", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        for r in rows:
            writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(target + ".tmp", target)
    print(f"wrote {os.path.relpath(target, ROOT)}")


if __name__ == "__main__":
    main()
