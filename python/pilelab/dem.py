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

# The to_frame() columns: column, the array it comes from (name, component or None) and the SI
# unit the column's name promises, which must be the dataset's `unit` attribute (docs/FORMAT.md).
_GRAIN_COLUMNS = (("x_m", "position", 0, "m"), ("y_m", "position", 1, "m"), ("angle_rad", "angle", None, "rad"),
                  ("vx_m_per_s", "velocity", 0, "m/s"), ("vy_m_per_s", "velocity", 1, "m/s"),
                  ("omega_rad_per_s", "angular_velocity", None, "rad/s"),
                  ("contact_force_x_N", "contact_force", 0, "N"), ("contact_force_y_N", "contact_force", 1, "N"))
_CONTACT_COLUMNS = (("x_m", "point", 0, "m"), ("y_m", "point", 1, "m"), ("normal_x", "normal", 0, "1"),
                    ("normal_y", "normal", 1, "1"), ("normal_force_N", "normal_force", None, "N"),
                    ("tangential_force_N", "tangential_force", None, "N"), ("force_x_N", "force", 0, "N"),
                    ("force_y_N", "force", 1, "N"), ("overlap_area_m2", "overlap_area", None, "m^2"),
                    ("chord_m", "chord", None, "m"))


def _sized(shape, sizes):
    return tuple(sizes.get(d, d) for d in shape)


def _require_unit(path, field, found, expected):
    """A dataset's `unit` attribute must be the unit a column's name promises."""
    if found != expected:
        fail(path, field, f"attribute unit is {found!r}; expected {expected!r} (docs/FORMAT.md)")


def _columns(obj, spec, path, group_name):
    """The (column, array) pairs of spec for obj (a Snapshot or Contacts), units checked."""
    out = []
    for column, name, component, unit in spec:
        _require_unit(path, f"{group_name}/{name}", obj.units[name], unit)
        array = getattr(obj, name)
        out.append((column, array if component is None else array[:, component]))
    return out


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
        self.path, self.group_name = path_of(group), group.name
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

    def to_frame(self):
        """The contacts as a pandas DataFrame, one row per contact in the table's order: body_a,
        body_b (the pair), grain_a, grain_b (rows of the snapshot's arrays and of its
        to_frame(); -1 for a wall), wall (True: a is a wall), x_m, y_m (the force's point),
        normal_x, normal_y (n, from a to b), normal_force_N, tangential_force_N, force_x_N,
        force_y_N (on b; a gets the opposite), overlap_area_m2, chord_m. Each column's unit is
        its dataset's `unit` attribute, checked. Needs pandas (Debian's python3-pandas)."""
        import pandas
        columns = [("body_a", self.pair[:, 0]), ("body_b", self.pair[:, 1]), ("grain_a", self.grain_a),
                   ("grain_b", self.grain_b), ("wall", self.grain_a < 0)]
        columns += _columns(self, _CONTACT_COLUMNS, self.path, self.group_name)
        return pandas.DataFrame(dict(columns))


class Snapshot:
    """One instant: the active grains (ascending body index) and their contacts.

    Arrays (units in `units`): body, position (n, 2) m, angle rad, velocity (n, 2) m/s,
    angular_velocity rad/s, contact_force (n, 2) N, contact_count; wall_position,
    wall_angle, wall_velocity for the walls. `time_s` and `gravity_m_per_s2` are floats.
    """

    def __init__(self, dem, name, group):
        self.name = name
        self.dem = dem
        self.group_name = group.name
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

    def to_frame(self):
        """The grains as a pandas DataFrame, one row per grain in the snapshot's order (row i is
        grain i of the arrays, the row contacts.grain_a and grain_b name): body, x_m, y_m (the
        centroid), angle_rad, vx_m_per_s, vy_m_per_s, omega_rad_per_s, contact_force_x_N,
        contact_force_y_N (the contacts' sum, gravity not included), contact_count (contacts
        touching the grain, walls included), area_m2, mass_kg, is_disc, corners (a polygon's
        vertices; 0 for a disc). Each column's unit is its dataset's `unit` attribute, checked.
        Needs pandas (Debian's python3-pandas)."""
        import pandas
        b, bu = self.dem.bodies, self.dem.body_units
        columns = [("body", self.body)] + _columns(self, _GRAIN_COLUMNS, self.dem.path, self.group_name)
        columns.append(("contact_count", self.contact_count))
        for column, name, unit in (("area_m2", "area", "m^2"), ("mass_kg", "mass", "kg")):
            _require_unit(self.dem.path, f"/bodies/{name}", bu[name], unit)
            columns.append((column, b[name][self.body]))
        columns += [("is_disc", b["kind"][self.body] == 1), ("corners", np.diff(b["vertex_offset"])[self.body])]
        return pandas.DataFrame(dict(columns))

    def coordination_number(self, walls=True):
        """The mean number of contacts per grain over the snapshot's N grains (rattlers, with no
        contact, included), from the contact table: (2 C_gg + C_gw) / N with walls=True, each
        grain-grain contact counted at both its grains and a grain-wall contact (plate, side
        walls, a base of fixed grains) once, at its grain (the mean of contact_count); 2 C_gg / N
        with walls=False. Every contact of the table counts, whatever its force. NaN for no
        grains."""
        if len(self) == 0:
            return float("nan")
        on_wall = int(np.count_nonzero(self.contacts.grain_a < 0))
        between = len(self.contacts) - on_wall
        return (2 * between + (on_wall if walls else 0)) / len(self)

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
