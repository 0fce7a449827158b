#!/usr/bin/python3
"""The later stages of the paper study on the members poured so far, and the compact products
that the tables and figures are computed from (docs/studies/paper.md).

    /usr/bin/python3 studies/paper/stages.py SCENE STUDY_DIR OUT [--pilelab BIN]

SCENE is the ensemble's scene (scenes/paper-symmetric.toml), STUDY_DIR its archive
(docs/studies/paper/symmetric: data/<seed>/ holds the poured members). For each variant below,
the archived members are restored into OUT/<variant>/members/, the scene is rewritten with
`[ensemble] seeds = [...]` naming exactly those members (so nothing is poured) and the variant's
settings, and `pilelab run` makes the mesh, the coarse fields, the continuum models and the
comparison of that ensemble. Then its products go to STUDY_DIR/products/ (the scene as it is)
or STUDY_DIR/products_<variant>/, with the scene they were made from: some megabytes in all. studies/paper/tables.py needs nothing
else.

The variants (VARIANTS): the scene's own settings (the paper's 150 grains per RVE, a rough base
for elasticity); the RVE of the size the RVE study chooses (coarse.rve_grain_count = 0); and
elasticity with a smooth base.
"""
import argparse
import gzip
import os
import re
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import study_members  # noqa: E402

# name -> (settings {table: {key: TOML value}}, the products kept)
ALL_PRODUCTS = ("fields.h5", "report.json", "profiles.csv", "rve_study.csv")
VARIANTS = {
    "": ({}, ALL_PRODUCTS),
    "rve_study": ({"coarse": {"rve_grain_count": "0"}}, ("fields.h5", "report.json", "profiles.csv")),
    "smooth_base": ({"continuum.elastic": {"base": '"smooth"'}}, ("report.json", "profiles.csv")),
}


def archived_seeds(study):
    data = os.path.join(study, "data")
    return sorted(int(s) for s in os.listdir(data) if os.path.exists(os.path.join(data, s, "dem.h5")))


def table_span(text, table):
    """(start, end) of the body of [table] in the TOML text: from after its header to the next
    header; None if it has none."""
    header = re.search(r"^\[" + re.escape(table) + r"\][^\n]*\n", text, re.M)
    if not header:
        return None
    following = re.compile(r"^\[", re.M).search(text, header.end())
    return header.end(), following.start() if following else len(text)


def scene_with(text, table, key, value):
    """The scene with `key = value` in [table] (replacing the key's line, or added at the top of
    the table, or in a table added at the end)."""
    span = table_span(text, table)
    if span is None:
        return text.rstrip("\n") + f"\n\n[{table}]\n{key} = {value}\n"
    begin, end = span
    body = text[begin:end]
    line = re.compile(r"^" + re.escape(key) + r"\s*=.*$", re.M)
    body = line.sub(f"{key} = {value}", body, count=1) if line.search(body) else f"{key} = {value}\n" + body
    return text[:begin] + body + text[end:]


def scene_with_seeds(scene_text, seeds):
    """The scene with its [ensemble] table replaced by one naming the seeds."""
    span = table_span(scene_text, "ensemble")
    if span is None:
        sys.exit("stages.py: the scene has no [ensemble] table")
    table = "# The members poured so far (studies/paper/stages.py).\nseeds = [%s]\n\n" % ", ".join(map(str, seeds))
    return scene_text[:span[0]] + table + scene_text[span[1]:]


def repack(source, target):
    """An HDF5 file copied dataset by dataset with gzip and shuffle (the same names, types and
    attributes, except that every pile's own fields in /piles are kept in single precision:
    they serve the jackknife's statistics, which quote three digits), written to a temporary
    name and renamed."""
    def copy_attrs(a, b):
        for k, v in a.attrs.items():
            b.attrs[k] = v

    tmp = target + ".tmp"
    with h5py.File(source, "r") as src, h5py.File(tmp, "w", libver=("v108", "latest")) as dst:
        copy_attrs(src, dst)

        def visit(name, obj):
            if isinstance(obj, h5py.Group):
                copy_attrs(obj, dst.require_group(name))
                return
            data = obj[()]
            if name.startswith("piles/") and data.dtype == np.float64:
                data = data.astype(np.float32)
            if obj.shape and obj.size > 16:
                d = dst.create_dataset(name, data=data, compression="gzip", compression_opts=6, shuffle=True)
            else:
                d = dst.create_dataset(name, data=data)
            copy_attrs(obj, d)

        src.visititems(visit)
    os.replace(tmp, target)


def keep_products(out, products, names):
    os.makedirs(products, exist_ok=True)
    for name in names:
        source = os.path.join(out, name)
        if name.endswith(".h5"):
            repack(source, os.path.join(products, name))
            continue
        target = os.path.join(products, name + (".gz" if name.endswith(".csv") else ""))
        with open(source, "rb") as src:
            data = src.read()
        with open(target + ".tmp", "wb") as dst:
            dst.write(gzip.compress(data, mtime=0) if target.endswith(".gz") else data)
        os.replace(target + ".tmp", target)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("study")
    parser.add_argument("out")
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build", "apps", "pilelab"))
    parser.add_argument("--variants", default=",".join(v or "scene" for v in VARIANTS),
                        help="which variants to run, comma-separated (scene, rve_study, smooth_base)")
    args = parser.parse_args()

    seeds = archived_seeds(args.study)
    if len(seeds) < 2:
        sys.exit(f"stages.py: {args.study}/data holds {len(seeds)} poured member(s); an ensemble needs 2")
    with open(args.scene, encoding="utf-8") as f:
        base_scene = scene_with_seeds(f.read(), seeds)
    for name in args.variants.split(","):
        variant = "" if name == "scene" else name
        if variant not in VARIANTS:
            sys.exit(f"stages.py: --variants: no variant {name!r} (known: scene, {', '.join(v for v in VARIANTS if v)})")
        settings, names = VARIANTS[variant]
        scene = base_scene
        for table, keys in settings.items():
            for key, value in keys.items():
                scene = scene_with(scene, table, key, value)
        out = os.path.join(args.out, variant or "scene")
        members = os.path.join(out, "members")
        os.makedirs(members, exist_ok=True)
        study_members.restore(members, args.study)
        scene_path = os.path.join(out, "study_scene.toml")
        with open(scene_path, "w", encoding="utf-8") as f:
            f.write(scene)
        print(f"stages.py: {len(seeds)} members ({', '.join(map(str, seeds))}), variant {name} -> {out}", flush=True)
        # --allow-unsettled: every pile is measured, an unfit one recorded in the report's status.
        subprocess.run([args.pilelab, "run", scene_path, "-o", out, "--no-figures", "--allow-unsettled"], check=True)
        products = os.path.join(args.study, "products" + (f"_{variant}" if variant else ""))
        keep_products(out, products, names)
        # The scene the products were made from, beside them.
        with open(os.path.join(products, "scene.toml.tmp"), "w", encoding="utf-8") as f:
            f.write(scene)
        os.replace(os.path.join(products, "scene.toml.tmp"), os.path.join(products, "scene.toml"))
        print(f"stages.py: products in {products}")


if __name__ == "__main__":
    main()
