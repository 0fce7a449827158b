#!/usr/bin/python3
"""Opens pilelab's DEM output with third-party readers, as a user's script would.

Usage: read_vtk_with_meshio.py DEM_H5 GRAINS_VTU N_GRAIN_CELLS CONTACTS_VTU N_CONTACT_CELLS
                               EMPTY_CONTACTS_VTU PVD WALLS_VTU N_WALL_CELLS

Checks the cell counts and cell-data names of the VTU files with meshio, the empty contacts
file and the .pvd with an XML parser (meshio 5.0 cannot read a grid with no cells), and the
groups, datasets, shapes and attributes of dem.h5 with h5py. Exits 1 with a message on the
first problem. Called by tests/dem/dem_file_test.cpp.
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np

GRAIN_ARRAYS = {"body": 1, "is_wall": 1, "velocity": 3, "angular_velocity": 1,
                "contact_force": 3, "contact_count": 1, "speed": 1, "angle": 1, "area": 1,
                "equivalent_radius": 1, "stress": 9, "pressure": 1}
CONTACT_ARRAYS = {"body_a": 1, "body_b": 1, "normal_force": 1, "tangential_force": 1,
                  "force": 3, "overlap_area": 1, "chord": 1}


def fail(message):
    print("read_vtk_with_meshio.py: " + message)
    sys.exit(1)


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def check_vtu(path, cell_type, expected_cells, arrays):
    mesh = meshio.read(path)
    cells = sum(len(block.data) for block in mesh.cells)
    if cells != expected_cells:
        fail(f"{path}: {cells} cells, expected {expected_cells}")
    if any(block.type != cell_type for block in mesh.cells):
        fail(f"{path}: cell types {[b.type for b in mesh.cells]}, expected only {cell_type}")
    if set(mesh.cell_data) != set(arrays):
        fail(f"{path}: cell data {sorted(mesh.cell_data)}, expected {sorted(arrays)}")
    for name, components in arrays.items():
        values = np.concatenate(mesh.cell_data[name])
        shape = (expected_cells,) if components == 1 else (expected_cells, components)
        if values.shape != shape:
            fail(f"{path}: {name} has shape {values.shape}, expected {shape}")
    if "TIME" not in mesh.field_data or "TimeValue" not in mesh.field_data:
        fail(f"{path}: no TIME and TimeValue field data")
    if not np.array_equal(mesh.field_data["TIME"], mesh.field_data["TimeValue"]):
        fail(f"{path}: TIME and TimeValue differ")
    return mesh


def check_walls(path, expected_cells):
    """The walls' block: every cell a wall, without stress."""
    mesh = check_vtu(path, "polygon", expected_cells, GRAIN_ARRAYS)
    if not (np.concatenate(mesh.cell_data["is_wall"]) == 1).all():
        fail(f"{path}: a cell that is not a wall")
    if (np.concatenate(mesh.cell_data["stress"]) != 0).any():
        fail(f"{path}: walls carry a stress")


def check_grains(path, expected_cells):
    mesh = check_vtu(path, "polygon", expected_cells, GRAIN_ARRAYS)
    body = np.concatenate(mesh.cell_data["body"])
    is_wall = np.concatenate(mesh.cell_data["is_wall"])
    if len(set(body)) != len(body):
        fail(f"{path}: repeated body indices")
    if (is_wall != 0).any():
        fail(f"{path}: a wall among the grains (walls have a block of their own)")
    speed = np.concatenate(mesh.cell_data["speed"])
    velocity = np.concatenate(mesh.cell_data["velocity"])
    if not np.allclose(speed, np.hypot(velocity[:, 0], velocity[:, 1]), rtol=1e-8, atol=0):
        fail(f"{path}: speed is not |velocity|")
    if not (velocity[:, 2] == 0).all():
        fail(f"{path}: velocity has a z component")
    # Per grain: the pressure is minus half the stress trace, the stress symmetric with a zero z
    # row and column, the equivalent radius that of a disc of the grain's area.
    stress = np.concatenate(mesh.cell_data["stress"])
    pressure = np.concatenate(mesh.cell_data["pressure"])
    area = np.concatenate(mesh.cell_data["area"])
    if not np.allclose(pressure, -0.5 * (stress[:, 0] + stress[:, 4]), rtol=1e-8, atol=1e-12 * np.abs(stress).max()):
        fail(f"{path}: pressure is not -(stress_xx + stress_yy)/2")
    if not (np.array_equal(stress[:, 1], stress[:, 3]) and (stress[:, [2, 5, 6, 7, 8]] == 0).all()):
        fail(f"{path}: stress is not a symmetric in-plane tensor")
    if not np.allclose(np.concatenate(mesh.cell_data["equivalent_radius"]), np.sqrt(area / np.pi), rtol=1e-8):
        fail(f"{path}: equivalent_radius is not sqrt(area / pi)")


def check_empty_contacts(path):
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
    if piece is None or piece.get("NumberOfCells") != "0" or piece.get("NumberOfPoints") != "0":
        fail(f"{path}: expected a Piece with no points and no cells")
    names = {a.get("Name") for a in piece.find("CellData")}
    if names != set(CONTACT_ARRAYS):
        fail(f"{path}: cell data {sorted(names)}, expected {sorted(CONTACT_ARRAYS)}")


def check_pvd(path):
    root = ET.parse(path).getroot()
    if root.get("type") != "Collection":
        fail(f"{path}: not a VTK Collection")
    datasets = root.findall("Collection/DataSet")
    if not datasets:
        fail(f"{path}: no DataSet entries")
    for d in datasets:
        float(d.get("timestep"))
        part = int(d.get("part"))
        names = ("grains", "contacts", "walls")
        if part >= len(names) or d.get("name") != names[part]:
            fail(f"{path}: part {part} is named {d.get('name')!r}, expected one of {names} by part")
        file = os.path.join(os.path.dirname(path), d.get("file"))
        if not os.path.exists(file):
            fail(f"{path}: lists {d.get('file')}, which does not exist")
        meshio.read(file)


BODY_DATASETS = {  # name: (trailing shape, unit or None)
    "kind": ((), None), "is_wall": ((), None), "mass": ((), "kg"),
    "moment_of_inertia": ((), "kg m^2"), "area": ((), "m^2"), "radius": ((), "m"),
    "bounding_radius": ((), "m"),
}
GRAIN_DATASETS = {
    "body": ((), None), "position": ((2,), "m"), "angle": ((), "rad"),
    "velocity": ((2,), "m/s"), "angular_velocity": ((), "rad/s"),
    "contact_force": ((2,), "N"), "contact_count": ((), None),
}
CONTACT_DATASETS = {
    "pair": ((2,), None), "point": ((2,), "m"), "normal": ((2,), "1"),
    "normal_force": ((), "N"), "tangential_force": ((), "N"), "force": ((2,), "N"),
    "overlap_area": ((), "m^2"), "chord": ((), "m"),
}
WALL_DATASETS = {"wall_position": ((2,), "m"), "wall_angle": ((), "rad"), "wall_velocity": ((2,), "m/s")}


def check_datasets(f, group, datasets, count):
    for name, (trailing, unit) in datasets.items():
        path = f"{group}/{name}"
        if path not in f:
            fail(f"{f.filename}: missing {path}")
        if f[path].shape != (count,) + trailing:
            fail(f"{f.filename}: {path} has shape {f[path].shape}, expected {(count,) + trailing}")
        if unit is not None and text(f[path].attrs.get("unit", b"")) != unit:
            fail(f"{f.filename}: {path} unit {f[path].attrs.get('unit')!r}, expected {unit!r}")


def check_dem_h5(path):
    with h5py.File(path, "r") as f:
        attrs = {"format": "pilelab-dem", "length_unit": "m", "time_unit": "s",
                 "mass_unit": "kg", "force_unit": "N"}
        for name, value in attrs.items():
            if text(f.attrs.get(name, b"")) != value:
                fail(f"{path}: root attribute {name} is {f.attrs.get(name)!r}, expected {value!r}")
        if int(f.attrs["format_version"]) != 1:
            fail(f"{path}: format_version {f.attrs['format_version']}")
        if "note" not in f.attrs:
            fail(f"{path}: no note attribute")
        text(f["scene"][()])
        if "seed" not in f["run"].attrs:
            fail(f"{path}: /run has no seed attribute")
        n = f["bodies/kind"].shape[0]
        check_datasets(f, "/bodies", BODY_DATASETS, n)
        offset = f["bodies/vertex_offset"][()]
        if offset.shape != (n + 1,) or f["bodies/vertices"].shape != (offset[-1], 2):
            fail(f"{path}: vertex_offset and vertices do not match")
        walls = int(f["bodies/is_wall"][()].sum())
        if walls > 0 and (f["bodies/mass"][:walls] != 0).any():
            fail(f"{path}: walls must have mass 0")
        order = text(f["snapshots"].attrs["order"])
        names = order.split(",") if order else []
        if sorted(names) != sorted(f["snapshots"].keys()):
            fail(f"{path}: order attribute {order!r} does not list the snapshot groups")
        for name in names:
            g = f["snapshots"][name]
            for a in ("time_s", "gravity_m_per_s2", "grain_count", "contact_count"):
                if a not in g.attrs:
                    fail(f"{path}: /snapshots/{name} has no attribute {a}")
            check_datasets(f, f"/snapshots/{name}", GRAIN_DATASETS, int(g.attrs["grain_count"]))
            check_datasets(f, f"/snapshots/{name}/contacts", CONTACT_DATASETS, int(g.attrs["contact_count"]))
            check_datasets(f, f"/snapshots/{name}", WALL_DATASETS, walls)
            normal = g["contacts/normal"][()]
            if len(normal) and not np.allclose(np.hypot(normal[:, 0], normal[:, 1]), 1.0):
                fail(f"{path}: /snapshots/{name}/contacts/normal is not unit")
            if (g["contacts/normal_force"][()] < 0).any():
                fail(f"{path}: /snapshots/{name}/contacts/normal_force is negative")


def main(argv):
    if len(argv) != 10:
        fail(__doc__)
    dem_h5, grains, n_grains, contacts, n_contacts, empty, pvd, walls, n_walls = argv[1:]
    check_grains(grains, int(n_grains))
    check_walls(walls, int(n_walls))
    check_vtu(contacts, "line", int(n_contacts), CONTACT_ARRAYS)
    check_empty_contacts(empty)
    check_pvd(pvd)
    check_dem_h5(dem_h5)
    print("read_vtk_with_meshio.py: all checks passed")


if __name__ == "__main__":
    main(sys.argv)
