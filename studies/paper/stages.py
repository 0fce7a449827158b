#!/usr/bin/python3
"""The later stages of the paper study on the members poured so far, and the compact products
that the tables and figures are computed from (docs/studies/paper.md).

    /usr/bin/python3 studies/paper/stages.py SCENE STUDY_DIR OUT [--pilelab BIN]

SCENE is the ensemble's scene (scenes/paper-symmetric.toml), STUDY_DIR its archive
(docs/studies/paper/symmetric: data/<seed>/ holds the poured members). The archived members are
restored into OUT/members/, the scene is rewritten with `[ensemble] seeds = [...]` naming exactly
those members (so nothing is poured), and `pilelab run` makes the mesh, the coarse fields, the
continuum models and the comparison of that ensemble in OUT. Then the products go to
STUDY_DIR/products/: fields.h5 repacked with compression, report.json, profiles.csv.gz and
rve_study.csv.gz, some megabytes in all. studies/paper/tables.py needs nothing else.
"""
import argparse
import os
import re
import gzip
import subprocess
import sys

import h5py

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import study_members  # noqa: E402

PRODUCTS = ("report.json", "profiles.csv", "rve_study.csv")  # the CSVs gzipped


def archived_seeds(study):
    data = os.path.join(study, "data")
    return sorted(int(s) for s in os.listdir(data) if os.path.exists(os.path.join(data, s, "dem.h5")))


def scene_with_seeds(scene_text, seeds):
    """The scene with its [ensemble] table replaced by one naming the seeds."""
    table = "[ensemble]\n# The members poured so far (studies/paper/stages.py).\nseeds = [%s]\n" % ", ".join(map(str, seeds))
    pattern = re.compile(r"^\[ensemble\]\n(?:(?!\[).*\n)*", re.M)
    if not pattern.search(scene_text):
        sys.exit("stages.py: the scene has no [ensemble] table")
    return pattern.sub(table + "\n", scene_text, count=1)


def repack(source, target):
    """An HDF5 file copied dataset by dataset with gzip and shuffle (the same names, types,
    attributes), written to a temporary name and renamed."""
    def copy_attrs(a, b):
        for k, v in a.attrs.items():
            b.attrs[k] = v

    tmp = target + ".tmp"
    with h5py.File(source, "r") as src, h5py.File(tmp, "w", libver=("v108", "latest")) as dst:
        copy_attrs(src, dst)

        def visit(name, obj):
            if isinstance(obj, h5py.Group):
                copy_attrs(obj, dst.require_group(name))
            elif obj.shape and obj.size > 16:
                d = dst.create_dataset(name, data=obj[()], compression="gzip", compression_opts=6, shuffle=True)
                copy_attrs(obj, d)
            else:
                d = dst.create_dataset(name, data=obj[()])
                copy_attrs(obj, d)

        src.visititems(visit)
    os.replace(tmp, target)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("study")
    parser.add_argument("out")
    parser.add_argument("--pilelab", default=os.path.join(ROOT, "build", "apps", "pilelab"))
    args = parser.parse_args()

    seeds = archived_seeds(args.study)
    if len(seeds) < 2:
        sys.exit(f"stages.py: {args.study}/data holds {len(seeds)} poured member(s); an ensemble needs 2")
    members = os.path.join(args.out, "members")
    os.makedirs(members, exist_ok=True)
    study_members.restore(members, args.study)
    with open(args.scene, encoding="utf-8") as f:
        scene = scene_with_seeds(f.read(), seeds)
    scene_path = os.path.join(args.out, "study_scene.toml")
    with open(scene_path, "w", encoding="utf-8") as f:
        f.write(scene)
    print(f"stages.py: {len(seeds)} members ({', '.join(map(str, seeds))}) -> {args.out}", flush=True)
    subprocess.run([args.pilelab, "run", scene_path, "-o", args.out], check=True)

    products = os.path.join(args.study, "products")
    os.makedirs(products, exist_ok=True)
    repack(os.path.join(args.out, "fields.h5"), os.path.join(products, "fields.h5"))
    for name in PRODUCTS:
        target = os.path.join(products, name + (".gz" if name.endswith(".csv") else ""))
        with open(os.path.join(args.out, name), "rb") as src:
            data = src.read()
        with open(target + ".tmp", "wb") as dst:
            dst.write(gzip.compress(data, mtime=0) if target.endswith(".gz") else data)
        os.replace(target + ".tmp", target)
    print(f"stages.py: products in {products}")


if __name__ == "__main__":
    main()
