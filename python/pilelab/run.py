"""A run directory: report.json, the scene, and the files of every stage, loaded on first use."""
import csv
import json
import math
import os
from collections import defaultdict
from dataclasses import dataclass

import numpy as np

from pilelab._check import FormatError, MissingFileError, fail
from pilelab.dem import DemFile
from pilelab.fields import Fields, Models


def _toml(text, source):
    """The scene's TOML text parsed (None before Python 3.11); source names where it came from."""
    try:
        import tomllib  # Python 3.11
    except ImportError:  # pragma: no cover
        return None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        fail(source, "/scene", f"not valid TOML ({e})")


def _cached(loader):
    """A read-only property that runs loader(self) on first use and keeps the result."""
    name = "_cached_" + loader.__name__

    def get(self):
        if name not in self.__dict__:
            self.__dict__[name] = loader(self)
        return self.__dict__[name]

    get.__doc__ = loader.__doc__
    return property(get)


@dataclass(frozen=True)
class PileGeometry:
    """The pile as the DEM stage measured it on its `settled` snapshot (dem/pile_shape.h),
    read from report.json's dem section, so that there is one apex, the report's: apex_x_m
    (dem.apex_x_m, the centre of the highest surface bin), apex_y_m (dem.height_m, the highest
    grain point above the plate top y = 0: the height h), half_width_m (R, dem.plate_force_dip.
    half_width_m: the half-width of the wedge of the pile's height and flanks,
    R = h (cot theta_left + cot theta_right) / 2, the R of the report's dip statistic),
    repose_angle_left_deg, repose_angle_right_deg (NaN where a flank has no angle, and then R
    too). source: where the values come from."""

    apex_x_m: float
    apex_y_m: float
    half_width_m: float
    repose_angle_left_deg: float
    repose_angle_right_deg: float
    source: str

    def x_over_R(self, x):
        """x' = (x - apex_x_m) / half_width_m of positions x [m]: 0 under the apex, +-1 at the
        wedge's feet. A ValueError when R is not known (a flank without an angle)."""
        if not (math.isfinite(self.half_width_m) and self.half_width_m > 0):
            angles = f"{self.repose_angle_left_deg}, {self.repose_angle_right_deg} deg"
            raise ValueError(f"{self.source}: no half-width R (a flank has no angle of repose: {angles}), "
                             "so no x' = (x - apex) / R")
        return (np.asarray(x, dtype=float) - self.apex_x_m) / self.half_width_m


def _wedge_half_width(height, left_deg, right_deg):
    """R = h (cot theta_left + cot theta_right) / 2, as dem/pile_run.cpp computes it (NaN when
    an angle is)."""
    def cot(deg):
        t = math.tan(math.radians(deg))
        return math.inf if t == 0 else 1.0 / t

    return 0.5 * height * (cot(left_deg) + cot(right_deg))


def _pile_geometry(path, report):
    """The PileGeometry of report (the dict of path, a report.json) from its dem section."""
    _require_file(path, "`pilelab run`")
    dem = report.get("dem")
    if not isinstance(dem, dict):
        raise KeyError(f"{path}: no dem section (the DEM stage has not finished here)")

    def number(key, value, nullable):
        if value is None and nullable:
            return math.nan
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            fail(path, f"dem.{key}", f"is {value!r}; expected a number{' or null' if nullable else ''}")
        return float(value)

    for key in ("apex_x_m", "height_m", "repose_angle_left_deg", "repose_angle_right_deg"):
        if key not in dem:
            fail(path, f"dem.{key}", "missing; expected the measured pile (docs/FORMAT.md)")
    height = number("height_m", dem["height_m"], False)
    left = number("repose_angle_left_deg", dem["repose_angle_left_deg"], True)
    right = number("repose_angle_right_deg", dem["repose_angle_right_deg"], True)
    dip = dem.get("plate_force_dip")
    if isinstance(dip, dict) and "half_width_m" in dip:
        half_width = number("plate_force_dip.half_width_m", dip["half_width_m"], True)
        source = f"{path}: dem"
    else:  # a report written before the dip statistic: R by the same formula
        half_width = _wedge_half_width(height, left, right)
        source = f"{path}: dem (R from height_m and the repose angles)"
    return PileGeometry(number("apex_x_m", dem["apex_x_m"], False), height, half_width, left, right, source)


def _mean_geometry(path, members):
    """An ensemble's pile as the later stages take it (apps/run_command.cpp, measured_pile): the
    members' mean apex, height and angles (each over the members with a value), and R of the
    wedge of those means."""
    each = [m.geometry() for m in members]

    def mean(name):
        values = [getattr(g, name) for g in each if math.isfinite(getattr(g, name))]
        return sum(values) / len(values) if values else math.nan

    height, left, right = mean("apex_y_m"), mean("repose_angle_left_deg"), mean("repose_angle_right_deg")
    return PileGeometry(mean("apex_x_m"), height, _wedge_half_width(height, left, right), left, right,
                        f"{path}: the means of its {len(each)} members' dem sections")


class Member:
    """One pile of an ensemble: its seed, directory, report and dem.h5."""

    def __init__(self, directory, seed):
        self.seed = int(seed)
        self.path = directory

    @_cached
    def report(self):
        return _read_json(os.path.join(self.path, "report.json"))

    @_cached
    def dem(self):
        return _if_exists(os.path.join(self.path, "dem.h5"), DemFile)

    def geometry(self):
        """This pile's PileGeometry, from its report.json."""
        return _pile_geometry(os.path.join(self.path, "report.json"), self.report)


class Run:
    """The outputs of `pilelab run` (or of any stage) in one directory.

    report: report.json as a dict ({} when missing). scene_text / scene: the scene (from
    dem.h5, or the solve's copy), as text and parsed. dem, fields, models: DemFile, Fields,
    Models, or None when the file is missing. profiles(source, quantity): the cuts of
    profiles.csv. members: the ensemble's piles (empty for one pile). geometry(): the pile's
    apex and half-width; base_pressure() and plate_load() along x or x' = (x - apex) / R."""

    def __init__(self, path):
        self.path = os.fspath(path)
        if not os.path.isdir(self.path):
            found = "a file" if os.path.exists(self.path) else "nothing"
            raise MissingFileError(f"{self.path}: expected a run directory, found {found} there")

    def file(self, name):
        return os.path.join(self.path, name)

    @_cached
    def report(self):
        return _read_json(self.file("report.json"))

    @_cached
    def dem(self):
        return _if_exists(self.file("dem.h5"), DemFile)

    @_cached
    def fields(self):
        return _if_exists(self.file("fields.h5"), Fields)

    @_cached
    def models(self):
        return _if_exists(self.file("models.h5"), Models)

    @_cached
    def _profile_table(self):
        return _read_profiles(self.file("profiles.csv"))

    def _scene_file(self):
        """The DemFile the scene comes from: the run's, else its first member's (or None)."""
        if self.dem is not None:
            return self.dem
        if self.members and self.members[0].dem is not None:
            return self.members[0].dem
        return None

    @property
    def scene_text(self):
        dem = self._scene_file()
        return dem.scene if dem is not None else ""

    @property
    def scene(self):
        dem = self._scene_file()
        return (_toml(dem.scene, dem.path) or {}) if dem is not None else {}

    @property
    def members(self):
        return [Member(os.path.join(self.path, directory), seed) for directory, seed in _ensemble_members(self)]

    def profiles(self, source=None, quantity=None):
        """profiles.csv: with source and quantity, a dict y_over_h -> structured array of
        (x_m, value, stderr) sorted by x; without them, the list of (source, quantity) pairs."""
        table = self._profile_table
        if source is None:
            return sorted(table)
        cuts = table.get((source, quantity), {})
        return {h: np.array(sorted(rows), dtype=[("x_m", float), ("value", float), ("stderr", float)])
                for h, rows in sorted(cuts.items())}

    def profiles_frame(self):
        """profiles.csv as a pandas DataFrame (columns source, quantity, y_over_h, x_m, value,
        stderr); needs pandas (Debian's python3-pandas)."""
        import pandas
        return pandas.read_csv(self.file("profiles.csv"))

    def geometry(self):
        """The pile's PileGeometry (apex, height, half-width R, flanks) from report.json's dem
        section; for an ensemble, the pile the later stages mesh: the members' mean apex, height
        and angles, and R of that mean wedge."""
        if self.members:
            return _mean_geometry(self.path, self.members)
        return _pile_geometry(self.file("report.json"), self.report)

    def base_pressure(self, source="dem", scaled=False):
        """sigma_yy / rho g h along the lowest cut: x [m], value, standard error (the profile the
        paper's Fig. 9A plots; compression positive). scaled=True: x' = (x - apex) / R of
        geometry() in place of x."""
        _require_file(self.file("profiles.csv"), "`pilelab coarse`")
        cuts = self.profiles(source, "sigma_yy")
        if not cuts:
            raise KeyError(f"{self.path}: profiles.csv has no sigma_yy rows of {source!r}")
        rows = cuts[min(cuts)]
        x = self.geometry().x_over_R(rows["x_m"]) if scaled else rows["x_m"]
        return x, rows["value"], rows["stderr"]

    def plate_load(self, scaled=False):
        """The plate's load as a load cell measures it (the vertical force of the grain-plate
        contacts per unit length, binned a grain diameter wide; the report's
        dem.plate_force_profile): x [m], load [N/m], standard error. One pile: its profile, with
        no error (zeros); an ensemble: the members' mean and its standard error. scaled=True:
        the bin centres as x' = (x - apex) / R of geometry(), the load unchanged in N/m, so
        that sum(load) * dx' = (plate force) / R."""
        piles = [(m.path, m.report) for m in self.members] or [(self.path, self.report)]
        for directory, report in piles:
            _require_file(os.path.join(directory, "report.json"), "`pilelab run`")
            if not isinstance(report.get("dem"), dict) or "plate_force_profile" not in report["dem"]:
                raise KeyError(f"{os.path.join(directory, 'report.json')}: no dem.plate_force_profile "
                               "(a pile poured before it was measured)")
        profiles = [_plate_profile(os.path.join(d, "report.json"), r["dem"]["plate_force_profile"]) for d, r in piles]
        x = profiles[0][0]
        if any(px.size != x.size for px, _ in profiles):
            raise FormatError(f"{self.path}: the members' dem.plate_force_profile have different numbers of bins; "
                              "expected the same bins")
        loads = np.array([load for _, load in profiles])
        stderr = loads.std(axis=0, ddof=1) / np.sqrt(len(loads)) if len(loads) > 1 else np.zeros_like(x)
        return (self.geometry().x_over_R(x) if scaled else x), loads.mean(axis=0), stderr


# What a run's directory holds when some stage has finished there.
_OUTPUTS = ("report.json", "dem.h5", "fields.h5", "models.h5", "pile.msh")


def load(path):
    """The run in directory path (see Run). A path that is not a directory, or a directory that
    holds none of a run's outputs (empty, or another folder named by mistake), is a FormatError
    (also a FileNotFoundError) naming it. Files are read, and checked, on first use: a damaged
    one is a FormatError naming the file and the field."""
    run = Run(path)
    if not any(os.path.exists(run.file(name)) for name in _OUTPUTS):
        raise MissingFileError(f"{run.path}: no run's outputs here (none of {', '.join(_OUTPUTS)}); "
                               "`pilelab run SCENE -o DIR` writes them")
    return run


def _require_file(path, writer):
    """For helpers that need a file the run may lack (its property is then None or empty)."""
    if not os.path.exists(path):
        raise MissingFileError(f"{path}: missing; {writer} writes it")


def _read_json(path):
    """A JSON file as a dict ({} when missing); a damaged or truncated one is an error naming it."""
    if not os.path.exists(path):
        return {}
    try:
        with open(path, encoding="utf-8") as f:
            value = json.load(f)
    except json.JSONDecodeError as e:
        raise FormatError(f"{path}: line {e.lineno}, column {e.colno}: not valid JSON ({e.msg}): "
                          "damaged, or written by a run that was killed") from None
    except UnicodeDecodeError as e:
        raise FormatError(f"{path}: byte {e.start}: not UTF-8 text; expected JSON") from None
    except OSError as e:  # a directory of that name, no permission
        raise FormatError(f"{path}: cannot read ({e.strerror}); expected a JSON file") from None
    if not isinstance(value, dict):
        raise FormatError(f"{path}: top level: found a JSON {type(value).__name__}; expected an object")
    return value


def _ensemble_members(run):
    """(directory, seed) of each member listed in report.json's ensemble.members."""
    path = run.file("report.json")
    ensemble = run.report.get("ensemble", {})
    members = ensemble.get("members", []) if isinstance(ensemble, dict) else None
    if not isinstance(members, list):
        fail(path, "ensemble.members", "expected a list of members")
    out = []
    for i, m in enumerate(members):
        ok = isinstance(m, dict) and isinstance(m.get("directory"), str) and isinstance(m.get("seed"), int)
        if not ok:
            fail(path, f"ensemble.members[{i}]", f"is {m!r}; expected an object with directory (a string) and seed "
                                                 "(an integer)")
        out.append((m["directory"], m["seed"]))
    return out


def _plate_profile(path, profile):
    """dem.plate_force_profile of one report: bin centres x_m and load_N_per_m, same length."""
    field = "dem.plate_force_profile"
    try:
        x = np.asarray(profile["x_m"], dtype=float)
        load = np.asarray(profile["load_N_per_m"], dtype=float)
    except (KeyError, TypeError, ValueError) as e:
        fail(path, field, f"expected x_m and load_N_per_m, lists of numbers ({type(e).__name__}: {e})")
    if x.ndim != 1 or load.shape != x.shape:
        fail(path, field, f"x_m has shape {x.shape}, load_N_per_m {load.shape}; expected two lists of one length")
    return x, load


def _if_exists(path, reader):
    return reader(path) if os.path.exists(path) else None


_PROFILE_COLUMNS = ("source", "quantity", "y_over_h", "x_m", "value", "stderr")


def _read_profiles(path):
    """profiles.csv as (source, quantity) -> y_over_h -> [(x_m, value, stderr)]; a missing
    column or a cell that is not a number is a FormatError naming the line and the column."""
    table = defaultdict(lambda: defaultdict(list))
    if not os.path.exists(path):
        return {}
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = csv.DictReader(f)
            missing = [c for c in _PROFILE_COLUMNS if c not in (rows.fieldnames or [])]
            if missing:
                fail(path, "line 1", f"no column {', '.join(missing)}; expected the columns {', '.join(_PROFILE_COLUMNS)}")
            for r in rows:
                numbers = [_csv_number(path, rows.line_num, r, c) for c in ("y_over_h", "x_m", "value", "stderr")]
                y_over_h, x, value, err = numbers
                table[(r["source"], r["quantity"])][y_over_h].append((x, value, 0.0 if err is None else err))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        fail(path, "the table", f"cannot read it ({e}); expected CSV text")
    return {k: dict(v) for k, v in table.items()}


def _csv_number(path, line, row, column):
    """The cell as a float; an empty stderr (a model's row) is None."""
    cell = row[column]
    if column == "stderr" and cell in ("", None):
        return None
    try:
        return float(cell)
    except (TypeError, ValueError):
        fail(path, f"line {line}, column {column}", f"is {cell!r}; expected a number")
