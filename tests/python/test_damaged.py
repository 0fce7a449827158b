"""The Python reader refuses what the C++ readers refuse: damaged copies of the tiny pipeline's
files (truncated, of a later version, with NaN, misshapen or missing datasets, indices out of
range) are each a pilelab.FormatError whose message starts with the file's path and names the
field, never a raw h5py, JSON or NoneType error or an array returned as if whole.

    PYTHONPATH=python PILELAB_RUN=OUT /usr/bin/python3 -m unittest tests/python/test_damaged.py
"""
import os
import shutil
import tempfile
import unittest

import h5py
import numpy as np

import pilelab

OUT = os.environ.get("PILELAB_RUN", "")
FILES = ("report.json", "dem.h5", "fields.h5", "models.h5", "profiles.csv")


def replace(f, name, data):
    """Dataset name of f rewritten with data (another shape or type), its attributes kept."""
    attrs = dict(f[name].attrs)
    del f[name]
    f.create_dataset(name, data=data)
    f[name].attrs.update(attrs)


class RefusalCase(unittest.TestCase):
    """A temporary directory, and the assertion of every case: a FormatError (a ValueError)
    whose message starts with the file's path and holds the fragments (the field and more)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pilelab_damaged_")
        self.addCleanup(shutil.rmtree, self.dir)

    def assertRefused(self, read, path, *fragments):
        with self.assertRaises(pilelab.FormatError) as caught:
            read()
        message = str(caught.exception)
        self.assertTrue(message.startswith(path + ":"), message)
        for fragment in fragments:
            self.assertIn(fragment, message)
        return message


class NotARun(RefusalCase):
    """No run's files at all, or a report.json that is not JSON: no copy of a run needed."""

    def test_an_empty_folder_is_refused_naming_it(self):
        message = self.assertRefused(lambda: pilelab.load(self.dir), self.dir, "no run's outputs here")
        self.assertIn("report.json", message)

    def test_a_path_that_is_not_a_directory_is_refused_naming_it(self):
        path = os.path.join(self.dir, "report.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write("{}")
        self.assertRefused(lambda: pilelab.load(path), path, "expected a run directory, found a file")
        missing = os.path.join(self.dir, "nowhere")
        self.assertRefused(lambda: pilelab.load(missing), missing, "found nothing")

    def test_both_are_still_file_not_found_errors(self):
        # load() raised FileNotFoundError for these before FormatError existed.
        with self.assertRaises(FileNotFoundError):
            pilelab.load(self.dir)

    def test_report_that_is_not_json_names_the_line_and_column(self):
        path = os.path.join(self.dir, "report.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write('{"dem": {\n  "height_m": 0.3,,\n}}')
        run = pilelab.load(self.dir)
        self.assertRefused(lambda: run.report, path, "line 2, column", "not valid JSON")

    def test_report_that_is_not_an_object(self):
        path = os.path.join(self.dir, "report.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write("[1, 2]")
        self.assertRefused(lambda: pilelab.load(self.dir).report, path, "top level", "expected an object")


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class DamagedCopies(RefusalCase):
    """Copies of a real run, each damaged in one place with h5py."""

    def setUp(self):
        super().setUp()
        for name in FILES:
            shutil.copy(os.path.join(OUT, name), self.dir)
        self.run = pilelab.load(self.dir)

    def path(self, name):
        return os.path.join(self.dir, name)

    def damage(self, name, edit):
        with h5py.File(self.path(name), "r+") as f:
            edit(f)

    def test_the_undamaged_copy_reads(self):
        s = self.run.dem.snapshot("settled")
        self.assertGreater(len(s), 0)
        self.assertIn("stress_yy", self.run.fields)
        self.assertIn("elastic", self.run.models.names)

    def test_a_truncated_dem_file_names_it(self):
        path = self.path("dem.h5")
        os.truncate(path, os.path.getsize(path) // 2)
        self.assertRefused(lambda: self.run.dem, path, "/: cannot open as HDF5", "truncated")

    def test_a_later_format_version_is_refused_naming_the_value(self):
        for name in ("dem.h5", "fields.h5", "models.h5"):
            self.damage(name, lambda f: f.attrs.modify("format_version", 9))
        self.assertRefused(lambda: self.run.dem, self.path("dem.h5"), "format_version = 9")
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "format_version = 9")
        self.assertRefused(lambda: self.run.models, self.path("models.h5"), "format_version = 9")

    def test_another_format_is_refused(self):
        self.damage("fields.h5", lambda f: f.attrs.modify("format", "pilelab-models"))
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "format", "'pilelab-fields'")

    def test_a_position_that_is_nan_names_the_row(self):
        def nan_at_row_3(f):
            f["snapshots/settled/position"][3, 1] = np.nan
        self.damage("dem.h5", nan_at_row_3)
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           "/snapshots/settled/position: row 3, column 1 is NaN")

    def test_an_infinite_body_mass_is_refused_on_load(self):
        def infinite(f):
            f["bodies/mass"][5] = np.inf
        self.damage("dem.h5", infinite)
        self.assertRefused(lambda: self.run.dem, self.path("dem.h5"), "/bodies/mass: row 5 is infinite")

    def test_a_missing_dataset_is_named_by_its_path(self):
        self.damage("dem.h5", lambda f: f.__delitem__("snapshots/settled/contacts/normal"))
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           "/snapshots/settled/contacts/normal: missing dataset")
        self.damage("fields.h5", lambda f: f.__delitem__("mesh/nodes"))
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "/mesh/nodes: missing dataset")

    def test_a_listed_snapshot_that_is_missing_is_named(self):
        self.damage("dem.h5", lambda f: f.__delitem__("snapshots/relaxed"))
        self.assertRefused(lambda: self.run.dem, self.path("dem.h5"), "/snapshots/relaxed: missing group")

    def test_a_wrong_shape_names_both_shapes(self):
        def three_columns(f):
            v = f["snapshots/settled/velocity"][()]
            replace(f, "snapshots/settled/velocity", np.c_[v, np.zeros(len(v))])
        self.damage("dem.h5", three_columns)
        n = len(pilelab.load(OUT).dem.snapshot("settled"))
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           f"/snapshots/settled/velocity: shape ({n}, 3), expected ({n}, 2)")

    def test_a_contact_index_out_of_range_is_refused(self):
        bodies = len(pilelab.load(OUT).dem.bodies["kind"])

        def out_of_range(f):
            f["snapshots/settled/contacts/pair"][2, 1] = bodies
        self.damage("dem.h5", out_of_range)
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           f"/snapshots/settled/contacts/pair: row 2, column 1 is {bodies}; expected 0 .. {bodies - 1}")

    def test_a_contact_pair_out_of_order_is_refused(self):
        def swapped(f):
            pair = f["snapshots/settled/contacts/pair"]
            pair[0] = pair[0][::-1]
        self.damage("dem.h5", swapped)
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           "/snapshots/settled/contacts/pair: row 0", "a < b")

    def test_a_grain_index_that_is_a_wall_is_refused(self):
        self.damage("dem.h5", lambda f: f["snapshots/settled/body"].__setitem__(0, 0))
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           "/snapshots/settled/body: row 0 is 0", "a grain of /bodies")

    def test_a_count_attribute_that_disagrees_is_refused(self):
        self.damage("dem.h5", lambda f: f["snapshots/settled"].attrs.modify("contact_count", 7))
        self.assertRefused(lambda: self.run.dem.snapshot("settled"), self.path("dem.h5"),
                           "/snapshots/settled: attribute contact_count is 7")

    def test_a_triangle_index_out_of_range_is_refused(self):
        nodes = len(pilelab.load(OUT).fields.nodes)

        def out_of_range(f):
            f["mesh/triangles"][4, 2] = nodes
        self.damage("fields.h5", out_of_range)
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"),
                           f"/mesh/triangles: row 4, column 2 is {nodes}; expected 0 .. {nodes - 1}")

    def test_a_models_triangle_index_out_of_range_is_refused(self):
        self.damage("models.h5", lambda f: f["mesh/triangles"].__setitem__((0, 0), -1))
        self.assertRefused(lambda: self.run.models, self.path("models.h5"), "/mesh/triangles: row 0, column 0 is -1")

    def test_a_triangle_without_area_is_refused(self):
        def flat(f):
            t = f["mesh/triangles"]
            t[1] = [t[1][0], t[1][0], t[1][2]]
        self.damage("fields.h5", flat)
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "/mesh/triangles: row 1", "has no area")

    def test_a_counted_value_that_is_nan_is_refused_an_uncounted_one_kept(self):
        counted = pilelab.load(OUT).fields.count("stress_yy")
        row, empty = int(np.flatnonzero(counted > 0)[0]), np.flatnonzero(counted == 0)

        def nan_where_counted(f):
            f["fields/stress_yy"][row] = np.nan
        self.damage("fields.h5", nan_where_counted)
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), f"/fields/stress_yy: row {row} is nan where",
                           "/fields/stress_yy_count")
        if empty.size:  # where nothing was counted the value is unused, as in C++
            shutil.copy(os.path.join(OUT, "fields.h5"), self.dir)
            self.damage("fields.h5", lambda f: f["fields/stress_yy"].__setitem__(int(empty[0]), np.nan))
            self.assertTrue(np.isnan(pilelab.load(self.dir).fields["stress_yy"][empty[0]]))

    def test_a_count_whose_field_is_missing_is_named_as_itself(self):
        self.damage("fields.h5", lambda f: f.__delitem__("fields/pressure"))
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "/fields/pressure_count:",
                           "is missing")

    def test_points_that_do_not_match_the_mesh_are_refused(self):
        self.damage("fields.h5", lambda f: replace(f, "fields/points", f["fields/points"][:-1]))
        self.assertRefused(lambda: self.run.fields, self.path("fields.h5"), "/fields/points: has", "/mesh/nodes")

    def test_models_keep_nan_outside_the_mesh_but_refuse_nan_points(self):
        self.damage("models.h5", lambda f: f["elastic/pressure"].__setitem__(0, np.nan))
        self.assertTrue(np.isnan(pilelab.load(self.dir).models["elastic"]["pressure"][0]))
        self.damage("models.h5", lambda f: f["elastic/points"].__setitem__((0, 0), np.nan))
        self.assertRefused(lambda: self.run.models, self.path("models.h5"), "/elastic/points: row 0, column 0 is NaN")

    def test_a_missing_file_leaves_its_property_none_and_helpers_name_it(self):
        os.remove(self.path("fields.h5"))
        os.remove(self.path("profiles.csv"))
        run = pilelab.load(self.dir)
        self.assertIsNone(run.fields)
        self.assertRefused(run.base_pressure, self.path("profiles.csv"), "missing", "pilelab coarse")

    def test_a_damaged_profiles_table_names_the_line_and_column(self):
        with open(self.path("profiles.csv"), "a", encoding="utf-8") as f:
            f.write("dem,sigma_yy,0.1,not-a-number,1.0,\n")
        self.assertRefused(self.run.profiles, self.path("profiles.csv"), "column x_m", "expected a number")


if __name__ == "__main__":
    unittest.main()
