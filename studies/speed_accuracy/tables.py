#!/usr/bin/python3
"""The speed-accuracy study's table and Pareto figure, from its measurements alone
(docs/studies/speed_accuracy/data/*.json, written by run.py): docs/studies/speed_accuracy.md's
table between its markers, the same numbers as docs/studies/speed_accuracy/table.csv (value and
standard error in two columns each), and docs/studies/speed_accuracy/pareto.png.

    /usr/bin/python3 studies/speed_accuracy/tables.py [--data DIR] [--doc FILE] [--figures DIR]

Each setting is compared with its knob's reference (settings.REFERENCE). Both are ensembles of
the same seeds, so a difference is paired: its standard error is the jackknife of the
difference itself (each seed left out of both), which the shared grains and the settings that
reuse the same piles make much smaller than sqrt(se1^2 + se2^2) (used where the seeds differ).
The difference of two base pressure profiles is a relative L2 norm over the bins both have,
corrected for the noise of the difference: sqrt(max(0, sum d^2 - sum var_d)) / |p_ref|, beside its
noise floor sqrt(sum var_d) / |p_ref|, var_d each bin's jackknife variance. A knob's effect
counts when it exceeds two standard errors (or, for the profile, two noise floors).
"""
import argparse
import glob
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "studies", "paper"))
import settings as study  # noqa: E402
import tables as paper  # noqa: E402  (replace_between_markers)


def load(data):
    out = {}
    for path in sorted(glob.glob(os.path.join(data, "*.json"))):
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
        out[d["name"]] = d
    if "accurate" in out and "accurate_b" in out:
        p = pooled(out["accurate"], out["accurate_b"])
        if p is not None:
            out[POOLED] = p
    return out


POOLED = "accurate_pooled"


def pooled(a, b):
    """The numerical knobs' reference as the mean of its two realisations ("accurate" and
    "accurate_b", the same seeds poured by builds that round differently): each quantity and
    each leave-one-out value is the mean of the two ensembles' (so its jackknife is that of the
    mean of the two, paired by seed), each member's angles and costs the mean of its seed's two.
    Its variance is down to half of one realisation's as far as the two are independent, and a
    setting's difference from it keeps the pairing by seed. None where the two cannot be pooled
    (other seeds, or base profiles on other bins)."""
    if not (paired(a, b) and "members" in a and "members" in b):
        return None
    if a["base_profile"]["x_over_R"] != b["base_profile"]["x_over_R"]:
        return None
    by_seed = {m["seed"]: m for m in b["members"]}
    if sorted(by_seed) != sorted(m["seed"] for m in a["members"]):
        return None

    def mean_members(m, n):
        out = dict(m)
        for key in ("cpu_time_s", "wall_time_s", "repose_angle_left_deg", "repose_angle_right_deg", "height_m"):
            if m.get(key) is not None and n.get(key) is not None:
                out[key] = 0.5 * (m[key] + n[key])
        out["lost"] = 0.5 * (m["lost"] + n["lost"])
        return out

    def mean_lists(x, y):
        return (0.5 * (np.array(x, dtype=float) + np.array(y, dtype=float))).tolist()

    loo = {k: mean_lists(a["leave_one_out"][k], b["leave_one_out"][k])
           for k in a.get("leave_one_out", {}) if k in b.get("leave_one_out", {})}
    quantities = {}
    for k, (va, sa) in a["quantities"].items():
        vb, sb = b["quantities"].get(k, [None, None])
        if va is None or vb is None:
            continue
        se = jackknife_se(np.array(loo[k])) if k in loo else (0.5 * float(np.hypot(sa, sb)) if sa is not None and sb is not None else None)
        quantities[k] = [0.5 * (va + vb), se]
    pa, pb = a["base_profile"], b["base_profile"]
    if "leave_one_out" not in pa or "leave_one_out" not in pb:
        return None
    ploo = np.array(mean_lists(pa["leave_one_out"], pb["leave_one_out"]))
    profile = {"x_over_R": pa["x_over_R"], "value": mean_lists(pa["value"], pb["value"]),
               "stderr": paper.jackknife_se(ploo).tolist(), "leave_one_out": ploo.tolist()}
    return {"name": POOLED, "knob": "reference", "value": "verlet, 2e-6 s: the mean of both realisations",
            "seeds": a["seeds"], "members": [mean_members(m, by_seed[m["seed"]]) for m in a["members"]],
            "quantities": quantities, "leave_one_out": loo, "base_profile": profile}


def seconds(m):
    """A pile's cost: its processor time (core-seconds, unaffected by what else ran), else its
    wall time."""
    return m["cpu_time_s"] if m.get("cpu_time_s") else m["wall_time_s"]


def cost(d):
    """DEM processor time per pile (mean, SE), or the later stages' time."""
    if "members" not in d:
        return seconds(d), None
    t = np.array([seconds(m) for m in d["members"]])
    return float(t.mean()), float(t.std(ddof=1) / np.sqrt(len(t))) if len(t) > 1 else None


def later_cost(d):
    q = d["quantities"]
    return sum(q.get(k, [0.0])[0] or 0.0 for k in ("coarse_wall_time_s", "elastic_wall_time_s", "fpa_wall_time_s"))


def paired(d, ref):
    """Whether two settings' ensembles are of the same seeds in the same order."""
    return d.get("seeds") is not None and d.get("seeds") == ref.get("seeds")


def jackknife_se(leave_out):
    return float(paper.jackknife_se(leave_out))


def member_angle(m):
    """A pile's repose angle: the mean of its two flanks' (as the ensemble's pile_mean)."""
    return 0.5 * (m["repose_angle_left_deg"] + m["repose_angle_right_deg"])


def difference(d, ref, key, relative=False):
    a, sa = d["quantities"].get(key, [None, None])
    b, sb = ref["quantities"].get(key, [None, None])
    if a is None or b is None or sa is None or sb is None:
        return None, None
    diff = a - b
    la, lb = d.get("leave_one_out", {}).get(key), ref.get("leave_one_out", {}).get(key)
    if key == "repose_angle_pile_mean_deg" and paired(d, ref) and d.get("members") and ref.get("members"):
        # Each pile's own angles are measured: the difference of the means is the mean of the
        # piles' differences, and its standard error that of a paired sample.
        per_pile = np.array([member_angle(m) for m in d["members"]]) - np.array([member_angle(m) for m in ref["members"]])
        se = float(per_pile.std(ddof=1) / np.sqrt(len(per_pile))) if len(per_pile) > 1 else None
    elif paired(d, ref) and la is not None and lb is not None:
        se = jackknife_se(np.array(la, dtype=float) - np.array(lb, dtype=float))
    else:
        se = float(np.hypot(sa, sb))
    if relative:
        return diff / b, se / abs(b)
    return diff, se


def profile_l2(d, ref):
    p, q = d["base_profile"], ref["base_profile"]
    a, sa, b, sb = (np.array(x, dtype=float) for x in (p["value"], p["stderr"], q["value"], q["stderr"]))
    if paired(d, ref) and "leave_one_out" in p and "leave_one_out" in q:
        loo = np.array(p["leave_one_out"], dtype=float) - np.array(q["leave_one_out"], dtype=float)
        n = len(loo)
        var = (n - 1) / n * np.sum((loo - loo.mean(axis=0)) ** 2, axis=0)
    else:
        var = sa ** 2 + sb ** 2
    ok = np.isfinite(a) & np.isfinite(b) & np.isfinite(var) & (np.abs(np.array(p["x_over_R"])) < 0.9)
    if ok.sum() < 3:
        return None, None
    norm = np.sqrt(np.sum(b[ok] ** 2))
    noise = np.sum(var[ok])
    return float(np.sqrt(max(0.0, np.sum((a[ok] - b[ok]) ** 2) - noise)) / norm), float(np.sqrt(noise) / norm)


def fmt(v, s, digits=2, scale=1.0):
    if v is None or not np.isfinite(v):
        return "-"
    if s is None or not np.isfinite(s):
        return f"{v * scale:.{digits}f}"
    return f"{v * scale:+.{digits}f} ± {s * scale:.{digits}f}"


def rows(results):
    out = []
    order = [(s[0], None) for s in study.DEM] + [(a[0], a) for a in study.ALSO] + [(s[0], None) for s in study.LATER]
    for name, also in order:
        d = results.get(name)
        if d is None:
            continue
        if also:  # the same measurements as a point of another knob
            d = dict(d, knob=also[1], value=also[2])
        ref_name = study.REFERENCE[d["knob"]] or name
        ref = results.get(ref_name)
        later = name in {s[0] for s in study.LATER}
        is_reference = ref_name == name
        t, ts = (later_cost(d), None) if later else cost(d)
        t_ref = (later_cost(ref) if later else cost(ref)[0]) if ref else None
        cells = {"knob": d["knob"], "setting": d["value"], "reference": ref_name,
                 "time": f"{t:.1f}" + (f" ± {ts:.1f}" if ts else "") + (" (later stages)" if later else ""),
                 "speed": f"{t_ref / t:.2f}" if t_ref and t else "-"}
        flags = []
        numbers = {"time": (t, ts), "speed": ((t_ref / t) if t_ref and t else None, None)}
        cells["numbers"] = numbers

        def counted(v, s, label):
            if v is not None and s is not None and abs(v) > 2 * s:
                flags.append(label)

        if ref is not None and not is_reference:
            for key, label, digits, rel in (("repose_angle_pile_mean_deg", "angle", 1, False),
                                            ("stress_tilt_flanks_deg", "tilt", 1, False),
                                            ("fabric_trace_core", "tr F", 1, True),
                                            ("volume_fraction_core", "nu", 1, True),
                                            ("fit_E_N_per_m", "E", 0, True)):
                v, s = difference(d, ref, key, rel)
                cells[key] = fmt(v, s, digits, 100.0 if rel else 1.0)
                numbers[key] = (v, s)
                if key != "fit_E_N_per_m":
                    counted(v, s, label)
            l2, floor = profile_l2(d, ref)
            cells["profile"] = "-" if l2 is None else f"{l2:.3f} (noise {floor:.3f})"
            numbers["profile"] = (l2, floor)
            if l2 is not None and l2 > 2 * floor:
                flags.append("base profile")
            for model in ("elastic", "fpa"):
                v, s = difference(d, ref, f"{model}_relative_l2_stress_yy")
                cells[f"{model}_l2"] = fmt(v, s, 3)
                numbers[f"{model}_l2"] = (v, s)
        else:
            for key in ("repose_angle_pile_mean_deg", "stress_tilt_flanks_deg", "fabric_trace_core",
                        "volume_fraction_core", "fit_E_N_per_m", "profile", "elastic_l2", "fpa_l2"):
                cells[key] = "(reference)" if is_reference else "-"
        lost = 0 if later else sum(m["lost"] for m in d.get("members", []))
        cells["lost"] = lost
        if ref is None:
            cells["verdict"] = "its reference is not measured yet"
        else:
            cells["verdict"] = "-" if is_reference else ("differs: " + ", ".join(flags) if flags else "no effect beyond 2 SE")
        if lost:
            cells["verdict"] += f"; {lost} grains lost"
        out.append(cells)
    return out


COLUMNS = [("knob", "knob"), ("setting", "setting"), ("reference", "against"),
           ("time", "cost per pile (core-s)"), ("speed", "speed-up"),
           ("repose_angle_pile_mean_deg", "Δ repose angle (deg)"), ("profile", "base sigma_yy, rel. L2"),
           ("stress_tilt_flanks_deg", "Δ stress tilt, flanks (deg)"), ("fabric_trace_core", "Δ tr F, core (%)"),
           ("volume_fraction_core", "Δ nu, core (%)"), ("fit_E_N_per_m", "Δ fitted E (%)"),
           ("elastic_l2", "Δ elastic L2"), ("fpa_l2", "Δ FPA L2"), ("verdict", "verdict")]


def markdown(results, table):
    skin = [results[s[0]] for s in study.SKIN if s[0] in results]
    lines = ["| " + " | ".join(h for _, h in COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(str(r.get(k, "-")) for k, _ in COLUMNS) + " |" for r in table]
    if skin:
        lines += ["", "Neighbour skin (one pile each, seed 1; the grains must end where the default skin's do):", "",
                  "| skin | cost (core-s) | list builds | particle-steps/s | same grains as 0.3 |", "|---|---|---|---|---|"]
        for d in skin:
            lines.append(f"| {d['value']} | {seconds(d):.1f} | {d.get('neighbour_list_builds', '-')} | "
                         f"{d['particle_steps_per_s']:.3g} | {d.get('same_grain_positions_as_default_skin', '(reference)')} |")
    missing = [s[0] for s in study.DEM + study.LATER + study.SKIN if s[0] not in results]
    if missing:
        lines += ["", f"Not yet measured: {', '.join(missing)}."]
    return "\n".join(lines) + "\n"


# The table's numbers for other tools: (column, cell key, what the two numbers are).
CSV_COLUMNS = [("cost_per_pile", "time", "core-seconds per pile (DEM) or seconds of the later stages; its SE over piles"),
               ("speed_up", "speed", "the reference's cost over the setting's"),
               ("repose_angle_deg", "repose_angle_pile_mean_deg", "difference from the reference, deg; SE"),
               ("base_sigma_yy_relative_l2", "profile", "relative L2 against the reference; its noise floor"),
               ("stress_tilt_flanks_deg", "stress_tilt_flanks_deg", "difference, deg; SE"),
               ("fabric_trace_core", "fabric_trace_core", "relative difference (0.01 = 1 %); SE"),
               ("volume_fraction_core", "volume_fraction_core", "relative difference; SE"),
               ("fitted_E", "fit_E_N_per_m", "relative difference; SE"),
               ("elastic_l2_stress_yy", "elastic_l2", "difference of the relative L2; SE"),
               ("fpa_l2_stress_yy", "fpa_l2", "difference of the relative L2; SE")]


def csv_table(table, path):
    """The table as CSV with each quantity's value and standard error (or noise floor) in two
    columns, empty where not measured or for the references themselves; written to a
    temporary name and renamed."""
    import csv
    header = ["knob", "setting", "reference"]
    for column, _, _ in CSV_COLUMNS:
        header += [column, column + ("_noise" if column.endswith("relative_l2") else "_se")]
    header += ["grains_lost", "verdict"]
    number = lambda v: "" if v is None or not np.isfinite(v) else f"{v:.6g}"  # noqa: E731
    with open(path + ".tmp", "w", newline="", encoding="utf-8") as f:
        out = csv.writer(f)
        out.writerow(header)
        for r in table:
            row = [r["knob"], r["setting"], r["reference"]]
            for _, key, _ in CSV_COLUMNS:
                v, s = r["numbers"].get(key, (None, None))
                row += [number(v), number(s)]
            row += [r["lost"], r["verdict"].split(";")[0]]
            out.writerow(row)
    os.replace(path + ".tmp", path)


def pareto(results, path):
    """Three panels: the DEM knobs' piles cost against the base profile's and the repose angle's
    error, and the later stages' knobs (the same piles) cost against the base profile's error."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FormatStrFormatter, LogLocator
    later_names = {s[0] for s in study.LATER}
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    knobs = sorted({d["knob"] for d in results.values() if "members" in d})
    colours = {k: plt.get_cmap("tab20")(i % 20) for i, k in enumerate(knobs)}  # 12 knobs: tab10 would repeat
    panels = ((axes[0], False, "profile", "base sigma_yy: relative L2 against the reference",
               "DEM cost per pile (core-seconds, one core each)"),
              (axes[1], False, "repose_angle_pile_mean_deg", "|Δ repose angle| (deg)",
               "DEM cost per pile (core-seconds, one core each)"),
              (axes[2], True, "profile", "base sigma_yy: relative L2 against the reference",
               "coarse + continuum wall time (s, one core)"))
    for ax, later, key, label, xlabel in panels:
        for name, d in results.items():
            if "members" not in d or (name in later_names) != later:
                continue
            if later and d["knob"] in ("element degree", "mesh size"):
                continue  # they change the models only, not the coarse base profile: see the table
            ref = results.get(study.REFERENCE[d["knob"]] or name)
            if ref is None:
                continue
            t, ts = (later_cost(d), None) if later else cost(d)
            if ref is d:  # the reference: zero error by definition, drawn for its cost
                v, s = 0.0, None
            elif key == "profile":
                v, s = profile_l2(d, ref)
            else:
                v, s = difference(d, ref, key)
                v = abs(v) if v is not None else None
            if v is None:
                continue
            marker = "s" if ref is d else "o"
            ax.errorbar(t, v, xerr=ts, yerr=s, fmt=marker, ms=5, color=colours[d["knob"]], capsize=2)
            ax.annotate(name, (t, v), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(FormatStrFormatter(""))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(label)
        ax.set_title("coarse-graining settings, on the base's piles" if later else "DEM settings, each its own piles",
                     fontsize=9)
    # The knobs' legend below the panels, where it covers no point.
    handles = [axes[0].plot([], [], "o", color=c, label=k)[0] for k, c in colours.items()]
    handles.append(axes[0].plot([], [], "s", color="grey", label="a knob's reference")[0])
    fig.legend(handles=handles, loc="lower center", ncol=len(handles) // 2 + 1, fontsize=7, frameon=False)
    n = max((len(d["members"]) for d in results.values() if "members" in d), default=0)
    fig.suptitle(f"Speed against accuracy: one point per setting, {n} piles each; error bars one SE "
                 "(the profile's: its noise floor); measured with other jobs on the 2-core machine, so the "
                 "DEM cost is processor time", fontsize=9)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    base = os.path.join(ROOT, "docs", "studies", "speed_accuracy")
    parser.add_argument("--data", default=os.path.join(base, "data"))
    parser.add_argument("--doc", default=os.path.join(ROOT, "docs", "studies", "speed_accuracy.md"))
    parser.add_argument("--figures", default=base)
    args = parser.parse_args()
    results = load(args.data)
    if not results:
        sys.exit(f"tables.py: no measurements in {args.data} (run studies/speed_accuracy/run.py)")
    paper.replace_between_markers(args.doc, "studies/speed_accuracy/tables.py", markdown(results, rows(results)))
    os.makedirs(args.figures, exist_ok=True)
    table = rows(results)
    csv_table(table, os.path.join(args.figures, "table.csv"))
    pareto(results, os.path.join(args.figures, "pareto.png"))
    print(f"tables.py: {len(results)} settings -> {args.doc}, {args.figures}/table.csv, {args.figures}/pareto.png")


if __name__ == "__main__":
    main()
