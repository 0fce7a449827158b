"""dem.h5: bodies, snapshots of the grains, the contact network (docs/FORMAT.md, "dem.h5")."""
import numpy as np

from pilelab._h5 import attribute, open_file, read, text

_GRAIN_ARRAYS = ("body", "position", "angle", "velocity", "angular_velocity", "contact_force", "contact_count")
_CONTACT_ARRAYS = ("pair", "point", "normal", "normal_force", "tangential_force", "force", "overlap_area", "chord")


class Contacts:
    """The contacts of a snapshot, ascending by body pair (a, b).

    pair: (c, 2) body indices a < b (a is the wall in a wall contact). grain_a, grain_b: the rows
    of a and b in the snapshot's grain arrays, -1 for a wall. normal points from a to b;
    normal_force and tangential_force act on b along n and t = (-n_y, n_x); force is the total
    force on b (N); the force on a is its opposite.
    """

    def __init__(self, group, grain_row):
        self.units = {}
        for name in _CONTACT_ARRAYS:
            setattr(self, name, read(group, name, self.units))
        pair = self.pair.reshape(-1, 2)
        self.grain_a = grain_row[pair[:, 0]]
        self.grain_b = grain_row[pair[:, 1]]
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
        self.time_s = float(attribute(group, "time_s"))
        self.gravity_m_per_s2 = float(attribute(group, "gravity_m_per_s2"))
        self.units = {}
        for a in _GRAIN_ARRAYS:
            setattr(self, a, read(group, a, self.units))
        for a in ("wall_position", "wall_angle", "wall_velocity"):
            setattr(self, a, read(group, a, self.units))
        grain_row = np.full(len(dem.bodies["mass"]), -1, dtype=np.int64)
        grain_row[self.body] = np.arange(len(self.body))
        self.contacts = Contacts(group["contacts"], grain_row)

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
    body, units in `body_units`), `snapshot_names` in the order taken, `snapshot(name)`."""

    def __init__(self, path):
        self.path = str(path)
        with open_file(self.path, "pilelab-dem") as f:
            self.format_version = attribute(f, "format_version")
            self.scene = text(f["scene"][()])
            self.run = {k: attribute(f["run"], k) for k in f["run"].attrs} if "run" in f else {}
            self.body_units = {}
            self.bodies = {k: read(f["bodies"], k, self.body_units) for k in f["bodies"]}
            order = attribute(f["snapshots"], "order", "")
            self.snapshot_names = [n for n in order.split(",") if n]
        self._snapshots = {}

    def snapshot(self, name=None):
        """The snapshot of that name; by default "settled" if there is one, else the last."""
        if name is None:
            name = "settled" if "settled" in self.snapshot_names else self.snapshot_names[-1]
        if name not in self.snapshot_names:
            raise KeyError(f"{self.path}: no snapshot {name!r} (the file has {', '.join(self.snapshot_names)})")
        if name not in self._snapshots:
            import h5py
            with h5py.File(self.path, "r") as f:
                self._snapshots[name] = Snapshot(self, name, f["snapshots"][name])
        return self._snapshots[name]

    @property
    def wall_count(self):
        return int(np.sum(self.bodies["is_wall"]))
