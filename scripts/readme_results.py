#!/usr/bin/python3
"""Writes README.md's "Results on the quick scene" from a run of scenes/quick.toml, so that its
numbers are this build's and cannot go stale.

    /usr/bin/python3 scripts/readme_results.py [OUT]            rewrite the section (and its two figures)
    /usr/bin/python3 scripts/readme_results.py --check [OUT]    exit 1 if README differs from OUT's numbers

OUT defaults to out/quick (`bash scripts/quickstart.sh`). The section lies between the markers
<!-- quick-results:begin --> and <!-- quick-results:end -->; everything in it is generated from
OUT/report.json, and the figures are copied from OUT/figures into docs/results/. The test suite
runs the quick scene and --check (tests/scripts/readme_results_test.sh): the same scene and seed
give the same files, so README matches the build exactly.
"""
import argparse
import json
import os
import shutil
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
README = os.path.join(ROOT, "README.md")
BEGIN, END = "<!-- quick-results:begin -->", "<!-- quick-results:end -->"
FIGURES = (("base_pressure.png", "quick_base_pressure.png"), ("fit_scatter.png", "quick_fit_scatter.png"))


def g(value, digits=2):
    """A number as the text gives it: `digits` significant figures, "n/a" for a missing one."""
    if value is None:
        return "n/a"
    return f"{value:.{digits}g}"


def interval(model, key):
    ci = model.get(key + "_ci95")
    return f" [{g(ci[0], 3)}, {g(ci[1], 3)}]" if ci and None not in ci else ""


def section(report):
    dem, mesh, coarse, cont = report["dem"], report["mesh"], report["coarse"], report.get("continuum", {})
    cmp, fit, status = report["compare"], report.get("fit", {}), report.get("status", {})
    models = cmp.get("models", {})
    dips = cmp.get("base_pressure_dip", {})
    lines = [
        f"`bash scripts/quickstart.sh` ({dem['particles']} grains in the pile, one pile, its outline meshed with "
        f"{mesh['nodes']} nodes, RVEs of {g(coarse['rve_grain_count_target'], 3)} grains; the flanks measure "
        f"{dem['repose_angle_left_deg']:.1f} and {dem['repose_angle_right_deg']:.1f} degrees). The run's status is "
        f"**{status.get('level', 'n/a')}** with {len(status.get('warnings', []))} finding(s) (report.json, \"status\").",
        "",
        "![base pressure](docs/results/quick_base_pressure.png)",
        "",
        "Pressure under the pile (sigma_yy / rho g h at y = 0), centre over maximum (below 1: a dip under the apex) "
        "and where the maximum lies (in half-widths R from the axis):",
        "",
        "| source | centre / maximum | maximum at x / R |",
        "|---|---|---|",
    ]
    for source in ("dem", "elastic", "fpa", "osl"):
        if source in dips:
            d = dips[source]
            lines.append(f"| {source} | {g(d['centre_over_max'])} | {g(d['x_of_max_over_R'])} |")
    lines += ["", "Each model against the DEM over the pile: relative L2 differences and the mean angle between the "
              "major stress axes (the FPA with the pile's own repose angles; the OSL with the constants fitted to "
              "the DEM's stress, `compare.osl_closure_fit`):", "",
              "| model | sigma_xx | sigma_yy | sigma_xy | axis angle [deg] | base force / weight |", "|---|---|---|---|---|---|"]
    osl = cmp.get("osl_closure_fit", {})
    rows = [(name, models[name], cont.get(name, {}).get("base_force_over_weight")) for name in models]
    if "closed_loop" in osl:
        rows.append((f"osl (eta {g(osl['eta'])}, mu {g(osl['mu'])}, R^2 {g(osl['r_squared'])})", osl["closed_loop"], None))
    for name, m, carried in rows:
        lines.append(f"| {name} | {g(m['relative_l2_stress_xx'])} | {g(m['relative_l2_stress_yy'])} | "
                     f"{g(m['relative_l2_stress_xy'])} | {g(m['principal_axis_angle_mean_deg'])} | "
                     f"{f'{carried:.4f}' if carried is not None else 'n/a'} |")
    mis = cmp.get("dem_misalignment", {})
    angle = lambda key: g(mis.get(key, {}).get("mean"))  # noqa: E731
    lines += ["", f"Within the DEM, the stress and strain axes differ by {angle('misalignment_stress_strain_deg')} "
              f"degrees on average, strain and fabric by {angle('misalignment_strain_fabric_deg')}, stress and "
              f"fabric by {angle('misalignment_stress_fabric_deg')} (the paper finds the three tensors not "
              "collinear; docs/studies/paper.md measures it on the paper's ensemble)."]
    if fit.get("models"):
        fm = fit["models"]
        lines += ["", f"Stress-strain fits to the 10 % gravity reduction ({fit['samples']} samples one RVE radius "
                  "apart; 95 % bootstrap intervals in brackets; N/m):", "",
                  "| model | constants | R^2 | AIC | CV rms [N/m] |", "|---|---|---|---|---|"]
        iso, ort, pd = fm.get("isotropic"), fm.get("orthotropic_fabric"), fm.get("pressure_dependent")
        if iso:
            lines.append(f"| isotropic | lambda = {g(iso['lambda_N_per_m'], 3)}{interval(iso, 'lambda_N_per_m')}, "
                         f"mu = {g(iso['mu_N_per_m'], 3)}{interval(iso, 'mu_N_per_m')} (E = {g(iso['E_N_per_m'], 3)}, "
                         f"nu = {g(iso['nu'])}) | {g(iso['r2'])} | {g(iso['aic'], 3)} | {g(iso['cv_rms_N_per_m'], 3)} |")
        if ort:
            lines.append("| orthotropic in the fabric frame | " + ", ".join(
                f"{c} = {g(ort[c + '_N_per_m'], 3)}" for c in ("C11", "C12", "C22", "C66")) +
                f" | {g(ort['r2'])} | {g(ort['aic'], 3)} | {g(ort['cv_rms_N_per_m'], 3)} |")
        if pd:
            lines.append(f"| pressure dependent | lambda0 = {g(pd['lambda0_N_per_m'], 3)}{interval(pd, 'lambda0_N_per_m')}, "
                         f"mu0 = {g(pd['mu0_N_per_m'], 3)}{interval(pd, 'mu0_N_per_m')}, n = {g(pd['exponent_n'])}"
                         f"{interval(pd, 'exponent_n')} | {g(pd['r2'])} | {g(pd['aic'], 3)} | {g(pd['cv_rms_N_per_m'], 3)} |")
        loop = fit.get("closed_loop", {})
        if "relative_l2_displacement" in loop:
            lines += ["", "The closed loop, elasticity solved with the fitted isotropic constants, misses the DEM's "
                      f"displacement field by a relative L2 difference of {g(loop['relative_l2_displacement'])}."]
        lines += ["", "![fit](docs/results/quick_fit_scatter.png)"]
    lines += ["", "One pile of 300 grains is a sample, not a finding: conclusions are drawn on ensembles "
              "(`[ensemble]`, docs/ENSEMBLES.md) and in the paper study (docs/studies/paper.md)."]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", default=os.path.join(ROOT, "out", "quick"))
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    with open(os.path.join(args.out, "report.json"), encoding="utf-8") as f:
        report = json.load(f)
    with open(README, encoding="utf-8") as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        sys.exit(f"readme_results.py: {README}: the markers {BEGIN} and {END} are missing")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    new = head + BEGIN + "\n" + section(report) + END + tail
    if args.check:
        if new != text:
            current = rest.split(END, 1)[0].strip("\n").split("\n")
            for a, b in zip(current, section(report).strip("\n").split("\n")):
                if a != b:
                    print(f"README:    {a}\nthis run:  {b}", file=sys.stderr)
            sys.exit(f"readme_results.py: README.md's quick-scene results differ from {args.out}'s: run "
                     "`bash scripts/quickstart.sh && /usr/bin/python3 scripts/readme_results.py` and commit")
        print("README.md's quick-scene results match", args.out)
        return
    with open(README + ".tmp", "w", encoding="utf-8") as f:
        f.write(new)
    os.replace(README + ".tmp", README)
    for source, target in FIGURES:
        path = os.path.join(args.out, "figures", source)
        if os.path.exists(path):
            shutil.copyfile(path, os.path.join(ROOT, "docs", "results", target))
    print("README.md: quick-scene results written from", args.out)


if __name__ == "__main__":
    main()
