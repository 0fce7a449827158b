"""dem.h5: bodies, snapshots of the grains, the contact network (docs/FORMAT.md, "dem.h5").
Read with the checks of the C++ reader (dem/dem_file.cpp): shapes, index ranges, finite numbers."""
import h5py
import numpy as np

from pilelab._check import fail, first, require_index_range
from pilelab._h5 import attribute, child, open_file, path_of, read, required_attribute, text

# name: shape, in grains n, walls w or contacts c. Every real number of a dem.h5 is finite.
_GRAIN_REALS = {"position": ("n", 2), "angle": ("n",), "velocity": ("n", 2), "angular_velocity": ("n",),
                "contact_force": ("n", 2)}
_WALL_ARRAYS = {"wall_position": ("w", 2), "wall_angle": ("w",), "wall_velocity": ("w", 2)}
_CONTACT_ARRAYS = {"point": ("c", 2), "normal": ("c", 2), "normal_force": ("c",), "tangential_force": ("c",),
                   "force": ("c", 2), "overlap_area": ("c",), "chord": ("c",)}
_BODY_REALS = ("mass", "moment_of_inertia", "area", "radius", "bounding_radius")


def _sized(shape, sizes):
    return tuple(sizes.get(d, d) for d in shape)


def _read_sized(group, names, units, sizes):
    """The datasets of names (name: shape in the letters of sizes), finite reals."""
    return {name: read(group, name, units, shape=_sized(shape, sizes), finite=True) for name, shape in names.items()}


class Contacts:
    """The contacts of a snapshot, ascending by body pair (a, b).

    pair: (c, 2) body indices a < b (a is the wall in a wall contact). grain_a, grain_b: the rows
    of a and b in the snapshot's grain arrays, -1 for a wall. normal points from a to b;
    normal_force and tangential_force act on b along n and t = (-n_y, n_x); force is the total
    force on b (N); the force on a is its opposite.
    """

    def __init__(self, group, grain_row, wall_count):
        self.units = {}
        self.pair = read(group, "pair", self.units, shape=("c", 2), integers=True)
        _check_pairs(path_of(group), group.name + "/pair", self.pair, grain_row, wall_count)
        _require_count_attribute(group.parent, "contact_count", len(self.pair), group.name + "/pair")
        for name, array in _read_sized(group, _CONTACT_ARRAYS, self.units, {"c": len(self.pair)}).items():
            setattr(self, name, array)
        self.grain_a = grain_row[self.pair[:, 0]]
        self.grain_b = grain_row[self.pair[:, 1]]
        self.units.update(grain_a="", grain_b="")

    def __len__(self):
        return len(self.normal_force)


class Snapshot:
    """One instant: the active grains (ascending body index) and their contacts.

    Arrays (units in `units`): body, position (n, 2) m, angle rad, velocity (n, 2) m/s,
    angular_velocity rad/s, contact_force (n, 2) N, contact_count; wall_position,
    wall_angle, wall_velocity for the walls. `time_s` and `gravity_m_per_s2` are floats.
    """

    def __init__(self, dem, name, group):
        self.name = name
        self.dem = dem
        self.time_s = float(required_attribute(group, "time_s", float))
        self.gravity_m_per_s2 = float(required_attribute(group, "gravity_m_per_s2", float))
        self.units = {}
        body_count, wall_count = len(dem.bodies["kind"]), dem.wall_count
        self.body = read(group, "body", self.units, shape=("n",), integers=True)
        require_index_range(dem.path, group.name + "/body", self.body, wall_count, body_count,
                            f"a grain of /bodies, whose {wall_count} walls come first")
        repeated = first(np.bincount(self.body, minlength=body_count)[self.body] > 1)
        if repeated is not None:
            fail(dem.path, group.name + "/body", f"grain {self.body[repeated]} is named more than once (row {repeated})")
        _require_count_attribute(group, "grain_count", len(self.body), group.name + "/body")
        sizes = {"n": len(self.body), "w": wall_count}
        for name, array in _read_sized(group, {**_GRAIN_REALS, **_WALL_ARRAYS}, self.units, sizes).items():
            setattr(self, name, array)
        self.contact_count = read(group, "contact_count", self.units, shape=(len(self.body),), integers=True)
        grain_row = np.full(body_count, -1, dtype=np.int64)
        grain_row[self.body] = np.arange(len(self.body))
        self.contacts = Contacts(child(group, "contacts", h5py.Group), grain_row, wall_count)

    def __len__(self):
        return len(self.body)

    def area(self):
        """Each grain's area [m^2]."""
        return self.dem.bodies["area"][self.body]

    def polygons(self, disc_corners=24):
        """Each grain's outline in the world frame, a list of (k, 2) arrays [m]; a disc is drawn
        with disc_corners points."""
        b = self.dem.bodies
        out = []
        t = np.linspace(0.0, 2.0 * np.pi, disc_corners, endpoint=False)
        for body, p, a in zip(self.body, self.position, self.angle):
            if b["kind"][body] == 1:
                local = b["radius"][body] * np.c_[np.cos(t), np.sin(t)]
            else:
                local = b["vertices"][b["vertex_offset"][body]:b["vertex_offset"][body + 1]]
            c, s = np.cos(a), np.sin(a)
            out.append(p + local @ np.array([[c, s], [-s, c]]))
        return out

    def grain_stress(self):
        """Each grain's mean stress, (n, 2, 2) in N/m, tension positive (paper eq. 10 for one
        grain): sigma = (1/A) sum over its contacts of (x_c - x_g) (x) f_c, with f_c the force
        the contact puts on the grain."""
        c = self.contacts
        moment = np.zeros((len(self.body), 2, 2))
        for rows, sign in ((c.grain_b, 1.0), (c.grain_a, -1.0)):
            on = rows >= 0
            arm = c.point[on] - self.position[rows[on]]
            np.add.at(moment, rows[on], sign * arm[:, :, None] * c.force[on][:, None, :])
        stress = moment / self.area()[:, None, None]
        return 0.5 * (stress + np.transpose(stress, (0, 2, 1)))

    def grain_pressure(self):
        """Each grain's pressure -(sigma_xx + sigma_yy)/2 [N/m], compression positive."""
        s = self.grain_stress()
        return -0.5 * (s[:, 0, 0] + s[:, 1, 1])


class DemFile:
    """A dem.h5: `scene` (the TOML text), `run` (the run's settings), `bodies` (arrays of every
    body, units in `body_units`), `snapshot_names` in the order taken, `snapshot(name)`.
    A damaged file is a FormatError naming it and the dataset: the header and bodies are
    checked here, each snapshot when first read."""

    def __init__(self, path):
        self.path = str(path)
        with open_file(self.path, "pilelab-dem") as f:
            self.format_version = attribute(f, "format_version")
            self.scene = _read_scene(f)
            self.run = _read_run_settings(f)
            self.body_units = {}
            self.bodies = _read_bodies(child(f, "bodies", h5py.Group), self.body_units)
            self.snapshot_names = _read_snapshot_names(f)
        self._snapshots = {}

    def snapshot(self, name=None):
        """The snapshot of that name; by default "settled" if there is one, else the last."""
        if name is None:
            if not self.snapshot_names:
                fail(self.path, "/snapshots", "attribute order names no snapshot; expected at least one")
            name = "settled" if "settled" in self.snapshot_names else self.snapshot_names[-1]
        if name not in self.snapshot_names:
            raise KeyError(f"{self.path}: no snapshot {name!r} (the file has {', '.join(self.snapshot_names)})")
        if name not in self._snapshots:
            with open_file(self.path, "pilelab-dem") as f:
                self._snapshots[name] = Snapshot(self, name, child(f, f"snapshots/{name}", h5py.Group))
        return self._snapshots[name]

    @property
    def wall_count(self):
        return int(np.sum(self.bodies["is_wall"]))


def _read_scene(f):
    dataset = child(f, "scene", h5py.Dataset)
    try:
        value = dataset[()]
    except (OSError, RuntimeError) as e:
        fail(path_of(f), "/scene", f"cannot read the dataset ({e}): a damaged file")
    if not isinstance(value, (bytes, np.bytes_, str)):
        fail(path_of(f), "/scene", f"holds {type(value).__name__}; expected a string (the scene's TOML text)")
    try:
        return text(value)
    except UnicodeDecodeError as e:
        fail(path_of(f), "/scene", f"not UTF-8 text ({e})")


def _read_run_settings(f):
    """/run's attributes (the group is absent when the run recorded no settings)."""
    if "run" not in f:
        return {}
    group = child(f, "run", h5py.Group)
    return {k: attribute(group, k) for k in group.attrs}


def _read_snapshot_names(f):
    """The names in /snapshots' order attribute, each of which must be a group there."""
    group = child(f, "snapshots", h5py.Group)
    names = [n for n in required_attribute(group, "order", str).split(",") if n]
    for name in names:
        child(group, name, h5py.Group)  # listed but missing: named as /snapshots/NAME
    return names


def _read_bodies(group, units):
    """/bodies: every array of length n (vertex_offset n + 1), vertices (m, 2), with the C++
    reader's checks of their values."""
    kind = read(group, "kind", units, shape=("n",), integers=True)
    n = len(kind)
    bodies = {"kind": kind, "is_wall": read(group, "is_wall", units, shape=(n,), integers=True)}
    bodies.update({name: read(group, name, units, shape=(n,), finite=True) for name in _BODY_REALS})
    offset = read(group, "vertex_offset", units, shape=(n + 1,), integers=True)
    bodies["vertex_offset"] = offset
    _check_vertex_offset(path_of(group), group.name + "/vertex_offset", offset, kind)
    bodies["vertices"] = read(group, "vertices", units, shape=(int(offset[-1]), 2), finite=True)
    _check_bodies(path_of(group), group.name, bodies)
    return bodies


def _check_vertex_offset(path, field, offset, kind):
    if offset[0] != 0:
        fail(path, field, f"starts at {offset[0]}; expected 0")
    corners = np.diff(offset)
    bad = first(corners < 0)
    if bad is not None:
        fail(path, field, f"decreases at row {bad + 1}; expected a non-decreasing sequence")
    bad = first((kind == 0) & (corners < 3))
    if bad is not None:
        fail(path, field, f"body {bad} is a polygon with {corners[bad]} vertices; expected at least 3")
    bad = first((kind == 1) & (corners != 0))
    if bad is not None:
        fail(path, field, f"body {bad} is a disc with {corners[bad]} vertices; expected none")


def _check_bodies(path, group, bodies):
    """Flags 0 or 1, walls before grains, and a grain's mass, moment, area (and a disc's radius)
    positive: what the C++ reader refuses."""
    for name, meaning in (("kind", "0 (polygon) or 1 (disc)"), ("is_wall", "0 (grain) or 1 (wall)")):
        bad = first((bodies[name] != 0) & (bodies[name] != 1))
        if bad is not None:
            fail(path, f"{group}/{name}", f"row {bad} is {bodies[name][bad]}; expected {meaning}")
    is_wall = bodies["is_wall"] == 1
    bad = first(is_wall[1:] & ~is_wall[:-1])
    if bad is not None:
        fail(path, f"{group}/is_wall", f"row {bad + 1} is a wall after a grain; expected the walls first")
    for name in ("mass", "moment_of_inertia", "area"):
        bad = first(~is_wall & ~(bodies[name] > 0))
        if bad is not None:
            fail(path, f"{group}/{name}", f"row {bad} (a grain) is {bodies[name][bad]}; expected a positive value")
    bad = first(~is_wall & (bodies["kind"] == 1) & ~(bodies["radius"] > 0))
    if bad is not None:
        fail(path, f"{group}/radius", f"row {bad} (a disc) is {bodies['radius'][bad]}; expected a positive radius")


def _require_count_attribute(group, name, length, dataset):
    """A snapshot's grain_count or contact_count attribute, which must be dataset's length."""
    value = required_attribute(group, name, int)
    if value != length:
        fail(path_of(group), group.name, f"attribute {name} is {value}; expected {length}, the length of {dataset}")


def _check_pairs(path, field, pair, grain_row, wall_count):
    """Each row two body indices a < b, each a wall or a grain of the snapshot (grain_a and
    grain_b index the snapshot's arrays with them)."""
    require_index_range(path, field, pair, 0, len(grain_row), "a body of /bodies")
    bad = first(pair[:, 0] >= pair[:, 1])
    if bad is not None:
        fail(path, field, f"row {bad} is ({pair[bad, 0]}, {pair[bad, 1]}); expected body indices a < b")
    absent = (pair >= wall_count) & (grain_row[pair] < 0)
    bad = first(absent)
    if bad is not None:
        row, column = divmod(bad, 2)
        fail(path, field, f"row {row}, column {column} is body {pair[row, column]}, a grain that is not in this "
                          "snapshot's body; expected a wall or one of the snapshot's grains")
