#!/usr/bin/python3
"""Every file in OUT (recursively) opens and reads whole: HDF5 (every dataset), JSON, VTK XML,
gmsh MSH, CSV, TOML. Temporary files of writers (NAME.tmp.PID) are skipped: a killed writer
may leave one, and the next run removes it. Prints one line per unreadable file and exits 1
if there is any.

    /usr/bin/python3 tests/reliability/check_files_readable.py OUT
"""
import csv
import json
import os
import sys
import tomllib
import xml.etree.ElementTree as ET

import h5py


def read_hdf5(path):
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                obj[()]
            for key in obj.attrs:
                obj.attrs[key]
        f.visititems(visit)


def read_msh(path):
    text = open(path, encoding="utf-8").read()
    for section in ("$MeshFormat", "$Nodes", "$EndNodes", "$Elements", "$EndElements"):
        if section not in text:
            raise ValueError(f"no {section}")


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if rows and any(len(r) != len(rows[0]) for r in rows):
        raise ValueError("rows of different lengths")


READERS = {".h5": read_hdf5, ".json": lambda p: json.load(open(p, encoding="utf-8")),
           ".vtu": lambda p: ET.parse(p), ".pvtu": lambda p: ET.parse(p), ".pvd": lambda p: ET.parse(p),
           ".msh": read_msh, ".csv": read_csv, ".toml": lambda p: tomllib.loads(open(p, encoding="utf-8").read())}


def main():
    bad = []
    for root, _, files in os.walk(sys.argv[1]):
        for name in files:
            if ".tmp." in name:
                continue
            reader = READERS.get(os.path.splitext(name)[1])
            if reader is None:
                continue
            path = os.path.join(root, name)
            try:
                reader(path)
            except Exception as e:  # noqa: BLE001 - any failure to read is the finding
                bad.append(f"{path}: {type(e).__name__}: {e}")
    print("\n".join(bad) if bad else "every file reads")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
