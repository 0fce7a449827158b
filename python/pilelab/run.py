"""A run directory: report.json, the scene, and the files of every stage, loaded on first use."""
import csv
import json
import os
from collections import defaultdict

import numpy as np

from pilelab.dem import DemFile
from pilelab.fields import Fields, Models


def _toml(text):
    try:
        import tomllib  # Python 3.11
    except ImportError:  # pragma: no cover
        return None
    return tomllib.loads(text)


def _cached(loader):
    """A read-only property that runs loader(self) on first use and keeps the result."""
    name = "_cached_" + loader.__name__

    def get(self):
        if name not in self.__dict__:
            self.__dict__[name] = loader(self)
        return self.__dict__[name]

    get.__doc__ = loader.__doc__
    return property(get)


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


class Run:
    """The outputs of `pilelab run` (or of any stage) in one directory.

    report: report.json as a dict ({} when missing). scene_text / scene: the scene (from
    dem.h5, or the solve's copy), as text and parsed. dem, fields, models: DemFile, Fields,
    Models, or None when the file is missing. profiles(source, quantity): the cuts of
    profiles.csv. members: the ensemble's piles (empty for one pile)."""

    def __init__(self, path):
        self.path = os.fspath(path)
        if not os.path.isdir(self.path):
            raise FileNotFoundError(f"{self.path}: no such run directory")

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

    @property
    def scene_text(self):
        if self.dem is not None:
            return self.dem.scene
        if self.members and self.members[0].dem is not None:
            return self.members[0].dem.scene
        return ""

    @property
    def scene(self):
        return _toml(self.scene_text) or {}

    @property
    def members(self):
        e = self.report.get("ensemble", {})
        return [Member(os.path.join(self.path, m["directory"]), m["seed"]) for m in e.get("members", [])]

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

    def base_pressure(self, source="dem"):
        """sigma_yy / rho g h along the lowest cut: x [m], value, standard error (the profile the
        paper's Fig. 9A plots; compression positive)."""
        cuts = self.profiles(source, "sigma_yy")
        if not cuts:
            raise KeyError(f"{self.path}: profiles.csv has no sigma_yy rows of {source!r}")
        rows = cuts[min(cuts)]
        return rows["x_m"], rows["value"], rows["stderr"]


    def plate_load(self):
        """The plate's load as a load cell measures it (the vertical force of the grain-plate
        contacts per unit length, binned a grain diameter wide; the report's
        dem.plate_force_profile): x [m], load [N/m], standard error. One pile: its profile, with
        no error (zeros); an ensemble: the members' mean and its standard error."""
        piles = [m.report for m in self.members] or [self.report]
        profiles = [r.get("dem", {}).get("plate_force_profile") for r in piles]
        if not profiles or any(p is None for p in profiles):
            raise KeyError(f"{self.path}: a report without dem.plate_force_profile (a pile poured before it was measured)")
        x = np.asarray(profiles[0]["x_m"], dtype=float)
        loads = np.array([p["load_N_per_m"] for p in profiles], dtype=float)
        if loads.shape[1] != x.size:
            raise ValueError(f"{self.path}: the members' plate profiles have different bins")
        stderr = loads.std(axis=0, ddof=1) / np.sqrt(len(loads)) if len(loads) > 1 else np.zeros_like(x)
        return x, loads.mean(axis=0), stderr


# What a run's directory holds when some stage has finished there.
_OUTPUTS = ("report.json", "dem.h5", "fields.h5", "models.h5", "pile.msh")


def load(path):
    """The run in directory path (see Run). A directory that holds none of a run's outputs
    (empty, or another folder named by mistake) is an error naming it."""
    run = Run(path)
    if not any(os.path.exists(run.file(name)) for name in _OUTPUTS):
        raise FileNotFoundError(f"{run.path}: no run's outputs here (none of {', '.join(_OUTPUTS)}); "
                                "`pilelab run SCENE -o DIR` writes them")
    return run


def _read_json(path):
    """A JSON file as a dict ({} when missing); a damaged or truncated one is an error naming it."""
    if not os.path.exists(path):
        return {}
    with open(path, encoding="utf-8") as f:
        try:
            value = json.load(f)
        except json.JSONDecodeError as e:
            raise ValueError(f"{path}: not valid JSON ({e.msg} at line {e.lineno}, column {e.colno}): "
                             "damaged, or written by a run that was killed") from None
    if not isinstance(value, dict):
        raise ValueError(f"{path}: expected a JSON object, found {type(value).__name__}")
    return value


def _if_exists(path, reader):
    return reader(path) if os.path.exists(path) else None


def _read_profiles(path):
    table = defaultdict(lambda: defaultdict(list))
    if not os.path.exists(path):
        return {}
    with open(path, newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            err = float(r["stderr"]) if r["stderr"] not in ("", None) else 0.0
            table[(r["source"], r["quantity"])][float(r["y_over_h"])].append((float(r["x_m"]), float(r["value"]), err))
    return {k: dict(v) for k, v in table.items()}
