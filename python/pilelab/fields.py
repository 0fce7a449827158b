"""fields.h5 (coarse-grained DEM fields) and models.h5 (continuum models): docs/FORMAT.md.
Read with the checks of the C++ readers (compare/point_fields.cpp): shapes, node indices,
finite coordinates, and a number wherever a field was counted."""
import h5py
import numpy as np

from pilelab._check import fail, first, require_index_range
from pilelab._h5 import attribute, child, open_file, path_of, read, required_attribute

# In /fields but not a quantity with its count.
_FIELDS_NOT_QUANTITIES = ("points", "piles_with_data")


class Fields:
    """The DEM's fields on the mesh. `nodes` (n, 2) m and `triangles` (m, 3) are the mesh;
    `points` where the fields live (`location`: "nodes" or "cells"); `fields[Q]`, `stderr(Q)`
    and `count(Q)` per quantity; `has_data(Q)` is the mask of points with data; `attrs` holds
    the root attributes (rve_radius_m, height_m, rho_bulk_kg_per_m2, ...); `units[Q]`.
    Ensembles: `pile_values(k, Q)` is pile k's own value. A damaged file is a FormatError
    naming it and the dataset."""

    def __init__(self, path):
        self.path = str(path)
        self.units = {}
        with open_file(self.path, "pilelab-fields") as f:
            self.attrs = {k: attribute(f, k) for k in f.attrs}
            self.nodes, self.triangles = _read_mesh(child(f, "mesh", h5py.Group), self.units)
            g = child(f, "fields", h5py.Group)
            self.location = _read_location(g)
            self.points = read(g, "points", self.units, shape=("k", 2), finite=True)
            _check_points_match_mesh(g, self.location, len(self.points), len(self.nodes), len(self.triangles))
            self._values = _read_quantities(g, len(self.points), self.units)
            self._piles = _read_piles(child(f, "piles", h5py.Group), len(self.points)) if "piles" in f else {}
        self.names = sorted(k for k in self._values if not (k.endswith("_stderr") or k.endswith("_count"))
                            or k == "grain_count")

    def __getitem__(self, quantity):
        return self._values[quantity]

    def __contains__(self, quantity):
        return quantity in self._values

    def stderr(self, quantity):
        """Standard error over the piles (zeros for one pile)."""
        return self._values.get(quantity + "_stderr", np.zeros_like(self._values[quantity]))

    def count(self, quantity):
        return self._values[quantity + "_count"]

    def has_data(self, quantity):
        return self.count(quantity) > 0

    @property
    def pile_count(self):
        return int(self.attrs.get("piles", 1))

    def pile_values(self, pile, quantity):
        return self._piles[pile][quantity]

    @property
    def piles(self):
        """Ensembles: pile index -> {quantity: that pile's own values} (empty for one pile)."""
        return self._piles

    def triangulation(self):
        """A matplotlib Triangulation of the mesh (for tripcolor, tricontour)."""
        import matplotlib.tri as mtri
        return mtri.Triangulation(self.nodes[:, 0], self.nodes[:, 1], self.triangles)


class Models:
    """The continuum models: `names` (e.g. ["elastic", "fpa"]), `model(name)` a dict of arrays,
    `points(name)` (the first `vertex_count` are the mesh vertices, then the triangle centres),
    `triangles` (m, 3) in vertex indices, `units[name][Q]`, `attrs`. Values are NaN at points
    outside the mesh (the file's `note`), so NaN is kept; points must be finite. A damaged file
    is a FormatError naming it and the dataset."""

    def __init__(self, path):
        self.path = str(path)
        self.units = {}
        self._models = {}
        with open_file(self.path, "pilelab-models") as f:
            self.attrs = {k: attribute(f, k) for k in f.attrs}
            self.vertex_count = attribute(f, "vertex_count")
            self.triangles = None
            if "mesh" in f:
                self.vertex_count = required_attribute(f, "vertex_count", int)
                self.triangles = _read_triangles(child(f, "mesh", h5py.Group), self.vertex_count, {},
                                                 f"the root attribute vertex_count is {self.vertex_count}")
            for name in f:
                if name != "mesh":
                    self._models[name] = _read_model(child(f, name, h5py.Group), self.units.setdefault(name, {}))
        self.names = sorted(self._models)

    def model(self, name):
        return {k: v for k, v in self._models[name].items() if k != "_attrs"}

    def model_attrs(self, name):
        return self._models[name]["_attrs"]

    def points(self, name):
        return self._models[name]["points"]

    def __getitem__(self, name):
        return self.model(name)


def _read_mesh(group, units):
    """/mesh: nodes (n, 2) finite, triangles (t, 3) of node indices, each with an area."""
    nodes = read(group, "nodes", units, shape=("n", 2), finite=True)
    triangles = _read_triangles(group, len(nodes), units, f"{group.name}/nodes has {len(nodes)} rows")
    corners = nodes[triangles]
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    # Integrals weigh by area: a triangle without one is a damaged mesh, not a zero weight.
    bad = first(~(np.abs(edge1[:, 0] * edge2[:, 1] - edge1[:, 1] * edge2[:, 0]) > 0))
    if bad is not None:
        fail(path_of(group), f"{group.name}/triangles", f"row {bad} (nodes {', '.join(map(str, triangles[bad]))}) "
                                                        "has no area; expected a triangle")
    return nodes, triangles


def _read_triangles(group, node_count, units, why):
    triangles = read(group, "triangles", units, shape=("t", 3), integers=True)
    return require_index_range(path_of(group), f"{group.name}/triangles", triangles, 0, node_count, why)


def _read_location(group):
    location = required_attribute(group, "location", str)
    if location not in ("nodes", "cells"):
        fail(path_of(group), group.name, f"attribute location is {location!r}; expected 'nodes' or 'cells'")
    return location


def _check_points_match_mesh(group, location, points, nodes, triangles):
    expected, rows_of = (nodes, "/mesh/nodes") if location == "nodes" else (triangles, "/mesh/triangles")
    if points != expected:
        fail(path_of(group), f"{group.name}/points", f"has {points} rows; with location = {location!r} expected one "
                                                     f"per row of {rows_of} ({expected})")


def _read_quantities(group, k, units):
    """Every dataset of /fields but points, each (k,): a quantity Q comes with its count Q_count
    (and Q_stderr for an ensemble); Q must be finite where Q_count > 0 (elsewhere it is unused).
    A count or error whose quantity is missing is a damaged file, named as itself."""
    names = [n for n in group if n != "points"]
    values = {}
    for name in names:
        counted = name + "_count" in names
        owner = None if counted else _owner(name, names)
        if not counted and owner is None and name not in _FIELDS_NOT_QUANTITIES:
            fail(path_of(group), f"{group.name}/{name}", f"expected a quantity with its count {group.name}/{name}_count, "
                                                         "or the count or standard error of a quantity; the quantity it "
                                                         "belongs to is missing")
        holds_counts = name == "piles_with_data" or (owner is not None and name.endswith("_count"))
        values[name] = read(group, name, units, shape=(k,), integers=holds_counts)
    for name in names:
        if name + "_count" in names:
            _require_finite_where_counted(group, name, values[name], values[name + "_count"])
    return values


def _owner(name, names):
    """The quantity that name is the count or standard error of, if it is in names."""
    for tail in ("_count", "_stderr"):
        if name.endswith(tail) and len(name) > len(tail) and name[:-len(tail)] in names:
            return name[:-len(tail)]
    return None


def _require_finite_where_counted(group, name, values, count):
    bad = first((count > 0) & ~np.isfinite(values))
    if bad is not None:
        fail(path_of(group), f"{group.name}/{name}", f"row {bad} is {values[bad]} where {group.name}/{name}_count is "
                                                     f"{count[bad]}; expected a finite number")


def _read_piles(group, k):
    """/piles/K/Q of an ensemble: pile K's own values, (k,), NaN where that pile has no data."""
    piles = {}
    for key in group:
        if not key.isdigit():
            fail(path_of(group), f"{group.name}/{key}", "expected a pile index (a group named 0, 1, ...)")
        pile = child(group, key, h5py.Group)
        piles[int(key)] = {q: read(pile, q, {}, shape=(k,)) for q in pile}
    return piles


def _read_model(group, units):
    """One model's group: points (k, 2) finite, every other dataset (k,); NaN marks a point
    outside the mesh."""
    points = read(group, "points", units, shape=("k", 2), finite=True)
    model = {q: points if q == "points" else read(group, q, units, shape=(len(points),)) for q in group}
    model["_attrs"] = {k: attribute(group, k) for k in group.attrs}
    return model
