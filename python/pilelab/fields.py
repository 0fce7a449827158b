"""fields.h5 (coarse-grained DEM fields) and models.h5 (continuum models): docs/FORMAT.md."""
import numpy as np

from pilelab._h5 import attribute, open_file, read


class Fields:
    """The DEM's fields on the mesh. `nodes` (n, 2) m and `triangles` (m, 3) are the mesh;
    `points` where the fields live (`location`: "nodes" or "cells"); `fields[Q]`, `stderr(Q)`
    and `count(Q)` per quantity; `has_data(Q)` is the mask of points with data; `attrs` holds
    the root attributes (rve_radius_m, height_m, rho_bulk_kg_per_m2, ...); `units[Q]`.
    Ensembles: `pile_values(k, Q)` is pile k's own value."""

    def __init__(self, path):
        self.path = str(path)
        self.units = {}
        with open_file(self.path, "pilelab-fields") as f:
            self.attrs = {k: attribute(f, k) for k in f.attrs}
            self.nodes = read(f["mesh"], "nodes", self.units)
            self.triangles = read(f["mesh"], "triangles", self.units)
            g = f["fields"]
            self.location = attribute(g, "location")
            self.points = read(g, "points", self.units)
            self._values = {k: read(g, k, self.units) for k in g if k != "points"}
            self._piles = {}
            if "piles" in f:
                for k in f["piles"]:
                    self._piles[int(k)] = {q: f["piles"][k][q][()] for q in f["piles"][k]}
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
    `triangles` (m, 3) in vertex indices, `units[name][Q]`, `attrs`."""

    def __init__(self, path):
        self.path = str(path)
        self.units = {}
        self._models = {}
        with open_file(self.path, "pilelab-models") as f:
            self.attrs = {k: attribute(f, k) for k in f.attrs}
            self.vertex_count = attribute(f, "vertex_count")
            self.triangles = f["mesh/triangles"][()] if "mesh" in f else None
            for name in f:
                if name == "mesh":
                    continue
                u = self.units.setdefault(name, {})
                self._models[name] = {q: read(f[name], q, u) for q in f[name]}
                self._models[name]["_attrs"] = {k: attribute(f[name], k) for k in f[name].attrs}
        self.names = sorted(self._models)

    def model(self, name):
        return {k: v for k, v in self._models[name].items() if k != "_attrs"}

    def model_attrs(self, name):
        return self._models[name]["_attrs"]

    def points(self, name):
        return self._models[name]["points"]

    def __getitem__(self, name):
        return self.model(name)
