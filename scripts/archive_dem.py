#!/usr/bin/python3
"""A dem.h5 in the compact form kept in the repository for long studies (docs/studies/paper/).

    /usr/bin/python3 scripts/archive_dem.py IN/dem.h5 OUT/dem.h5 [--min-size N]

The archive is itself a dem.h5 that every stage reads as it is: the same datasets, attributes
and scene, stored in single precision (integers in the smallest type that holds them), with
HDF5's shuffle and deflate filters; HDF5 converts back to double on reading. The grains'
positions and angles stay in double precision: displacements and strains are differences of
them between snapshots, micrometres on a metre. Velocities of the snapshots are stored as zeros
(a settled pile's are round-off, and no later stage reads them). Single precision elsewhere
(contact points, normals, forces, corners) changes the coarse fields by about 1e-5 of their
largest value (docs/studies/paper/README.md).
"""
import argparse
import os

import h5py
import numpy as np


def smallest_int(values):
    for t in (np.int8, np.int16, np.int32):
        info = np.iinfo(t)
        if values.size == 0 or (values.min() >= info.min and values.max() <= info.max):
            return t
    return np.int64


def copy(src, dst, min_size):
    for key, value in src.attrs.items():
        dst.attrs[key] = value
    for name, item in src.items():
        if isinstance(item, h5py.Group):
            copy(item, dst.create_group(name), min_size)
            continue
        data = item[()]
        if isinstance(data, np.ndarray) and data.size >= min_size and data.dtype.kind in "fi":
            if data.dtype.kind == "f":
                if name in ("velocity", "angular_velocity"):
                    data = np.zeros_like(data)
                if name not in ("position", "angle"):  # displacements are their differences
                    data = data.astype(np.float32)
            else:
                data = data.astype(smallest_int(data))
            out = dst.create_dataset(name, data=data, compression="gzip", compression_opts=9, shuffle=True,
                                     chunks=True)
        else:  # strings and small arrays (where chunks would cost more than they save): as they are
            src.copy(item, dst, name=name)
            continue
        for key, value in item.attrs.items():
            out.attrs[key] = value


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source")
    parser.add_argument("archive")
    parser.add_argument("--min-size", type=int, default=4096,
                        help="numeric datasets of fewer elements are copied as they are (default 4096)")
    args = parser.parse_args()
    with h5py.File(args.source, "r") as src, h5py.File(args.archive + ".tmp", "w") as dst:
        copy(src, dst, args.min_size)
    os.replace(args.archive + ".tmp", args.archive)


if __name__ == "__main__":
    main()
