"""The reader's analyses on a real run, each checked against something computed another way:
the DataFrames against the arrays they come from and against Newton's third law, the plate's
force summed over the contact table against the report, the coordination number against the
C++'s per-grain contact counts and a count of the pairs, the pile's apex against the highest
grain of the snapshot, and the base load along x' = (x - apex) / R against its integral in x.

    PYTHONPATH=python PILELAB_RUN=OUT /usr/bin/python3 -m unittest tests/python/test_analysis.py
"""
import copy
import importlib.util
import json
import math
import os
import shutil
import tempfile
import unittest

import h5py
import numpy as np

import pilelab

OUT = os.environ.get("PILELAB_RUN", "")

HAVE_PANDAS = importlib.util.find_spec("pandas") is not None


def weight(run, s):
    return run.dem.bodies["mass"][s.body].sum() * s.gravity_m_per_s2


def grain_tops(run, s):
    """The highest point of each grain: a polygon's highest corner in the world frame, a disc's
    centre plus its radius (dem/pile_shape.cpp's surface)."""
    b = run.dem.bodies
    return np.array([s.position[i, 1] + b["radius"][body] if b["kind"][body] == 1 else outline[:, 1].max()
                     for i, (body, outline) in enumerate(zip(s.body, s.polygons()))])


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class Analyses(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.result = pilelab.load(OUT)
        cls.s = cls.result.dem.snapshot("settled")  # the snapshot the report measures

    @unittest.skipUnless(HAVE_PANDAS, "pandas is not installed")
    def test_the_grains_frame_is_the_snapshots_arrays(self):
        s, b = self.s, self.result.dem.bodies
        f = s.to_frame()
        self.assertEqual(list(f.columns), ["body", "x_m", "y_m", "angle_rad", "vx_m_per_s", "vy_m_per_s",
                                           "omega_rad_per_s", "contact_force_x_N", "contact_force_y_N",
                                           "contact_count", "area_m2", "mass_kg", "is_disc", "corners"])
        self.assertEqual(len(f), len(s))
        for column, array in (("body", s.body), ("x_m", s.position[:, 0]), ("y_m", s.position[:, 1]),
                              ("angle_rad", s.angle), ("vx_m_per_s", s.velocity[:, 0]),
                              ("vy_m_per_s", s.velocity[:, 1]), ("omega_rad_per_s", s.angular_velocity),
                              ("contact_force_x_N", s.contact_force[:, 0]),
                              ("contact_force_y_N", s.contact_force[:, 1]), ("contact_count", s.contact_count),
                              ("area_m2", s.area())):
            np.testing.assert_array_equal(f[column].to_numpy(), array, err_msg=column)
        # Corners: those of each drawn outline (a disc is drawn with 24 points but has none).
        drawn = np.array([len(p) for p in s.polygons()])
        np.testing.assert_array_equal(np.where(f.is_disc, 24, f.corners), drawn)
        np.testing.assert_array_equal(f.is_disc, b["kind"][s.body] == 1)
        # Masses are the areal density times the area (docs/FORMAT.md): one density for every grain.
        density = self.result.scene.get("dem", {}).get("areal_density_kg_per_m2", 5000.0)  # the default
        np.testing.assert_allclose(f.mass_kg / f.area_m2, density, rtol=1e-12)

    @unittest.skipUnless(HAVE_PANDAS, "pandas is not installed")
    def test_the_contacts_frame_is_the_contact_table(self):
        c = self.s.contacts
        f = c.to_frame()
        self.assertEqual(len(f), len(c))
        self.assertEqual(list(f.columns), ["body_a", "body_b", "grain_a", "grain_b", "wall", "x_m", "y_m", "normal_x",
                                           "normal_y", "normal_force_N", "tangential_force_N", "force_x_N",
                                           "force_y_N", "overlap_area_m2", "chord_m"])
        for column, array in (("body_a", c.pair[:, 0]), ("body_b", c.pair[:, 1]), ("grain_a", c.grain_a),
                              ("grain_b", c.grain_b), ("x_m", c.point[:, 0]), ("y_m", c.point[:, 1]),
                              ("normal_x", c.normal[:, 0]), ("normal_y", c.normal[:, 1]),
                              ("normal_force_N", c.normal_force), ("tangential_force_N", c.tangential_force),
                              ("force_x_N", c.force[:, 0]), ("force_y_N", c.force[:, 1]),
                              ("overlap_area_m2", c.overlap_area), ("chord_m", c.chord)):
            np.testing.assert_array_equal(f[column].to_numpy(), array, err_msg=column)
        # wall: a is one of the walls, bodies 0 .. w-1 (read from /bodies, not from grain_a).
        np.testing.assert_array_equal(f.wall, self.result.dem.bodies["is_wall"][f.body_a] == 1)
        # The force on b is F_n n + F_t t with t = n turned by +90 degrees, t = (-n_y, n_x).
        scale = np.abs(c.force).max()
        np.testing.assert_allclose(f.force_x_N, f.normal_force_N * f.normal_x - f.tangential_force_N * f.normal_y,
                                   atol=1e-12 * scale)
        np.testing.assert_allclose(f.force_y_N, f.normal_force_N * f.normal_y + f.tangential_force_N * f.normal_x,
                                   atol=1e-12 * scale)

    @unittest.skipUnless(HAVE_PANDAS, "pandas is not installed")
    def test_the_plate_force_summed_over_the_contacts_frame_is_the_reports(self):
        f = self.s.contacts.to_frame()
        on_plate = f.wall & (f.body_a == 0)  # the plate is body 0
        self.assertAlmostEqual(f.force_y_N[on_plate].sum() / weight(self.result, self.s),
                               self.result.report["dem"]["plate_force_over_weight"], delta=1e-12)

    @unittest.skipUnless(HAVE_PANDAS, "pandas is not installed")
    def test_the_frames_join_into_each_grains_contact_force(self):
        # Newton's third law through a pandas join: +force on b, -force on a, summed per grain
        # row, is the C++'s contact_force of that grain.
        grains, f = self.s.to_frame(), self.s.contacts.to_frame()
        on_b = f.groupby("grain_b")[["force_x_N", "force_y_N"]].sum()
        on_a = -f[~f.wall].groupby("grain_a")[["force_x_N", "force_y_N"]].sum()
        total = on_b.add(on_a, fill_value=0.0).reindex(grains.index, fill_value=0.0)
        scale = np.abs(f[["force_x_N", "force_y_N"]].to_numpy()).max()
        np.testing.assert_allclose(total.to_numpy(), grains[["contact_force_x_N", "contact_force_y_N"]].to_numpy(),
                                   atol=1e-12 * scale)

    def test_coordination_number_counts_pairs(self):
        s = self.s
        n = len(s)
        is_wall = self.result.dem.bodies["is_wall"] == 1
        pair = s.contacts.pair
        between = np.count_nonzero(~is_wall[pair[:, 0]] & ~is_wall[pair[:, 1]])  # grain-grain pairs
        on_walls = len(pair) - between
        self.assertEqual(s.coordination_number(walls=False), 2 * between / n)
        self.assertEqual(s.coordination_number(walls=True), (2 * between + on_walls) / n)
        # The C++'s per-grain count (walls included) gives the same mean, and each grain's count
        # is its number of appearances in the pairs.
        self.assertAlmostEqual(s.coordination_number(), s.contact_count.mean(), delta=1e-12)
        appearances = np.bincount(np.searchsorted(s.body, pair[~is_wall[pair]]), minlength=n)
        np.testing.assert_array_equal(appearances, s.contact_count)
        self.assertGreater(s.coordination_number(), s.coordination_number(walls=False))  # the plate holds grains

    def test_geometry_is_the_reports_pile(self):
        g, d = self.result.geometry(), self.result.report["dem"]
        self.assertIsInstance(g, pilelab.PileGeometry)
        self.assertEqual((g.apex_x_m, g.apex_y_m), (d["apex_x_m"], d["height_m"]))
        self.assertEqual(g.half_width_m, d["plate_force_dip"]["half_width_m"])
        self.assertIn("report.json", g.source)
        # R is the half-width of the wedge of the height and the flanks: its feet lie h cot(theta)
        # either side of the apex.
        feet = g.apex_y_m / math.tan(math.radians(g.repose_angle_left_deg)) + \
            g.apex_y_m / math.tan(math.radians(g.repose_angle_right_deg))
        self.assertAlmostEqual(2 * g.half_width_m, feet, delta=1e-12 * feet)

    def test_geometry_is_the_pile_a_wedge_mesh_took(self):
        # A wedge meshed from the DEM's pile (mesh.kind = "wedge" without its own keys) took the
        # same apex, height and flanks (apps/run_command.cpp); the tiny pipeline meshes the outline.
        wedge = self.result.report.get("mesh", {}).get("wedge")
        if not (wedge and wedge.get("from_dem")):
            self.skipTest("the mesh is not a wedge filled from the DEM's pile")
        g = self.result.geometry()
        self.assertEqual((g.apex_x_m, g.apex_y_m, g.repose_angle_left_deg, g.repose_angle_right_deg),
                         (wedge["apex_x_m"], wedge["height_m"], wedge["left_angle_deg"], wedge["right_angle_deg"]))

    def test_the_apex_is_the_highest_grain_of_the_settled_snapshot(self):
        # The height is the highest grain point; the apex's x, the centre of the surface bin (two
        # mean diameters wide) that grain's centre lies in: within one mean diameter of it (the
        # plate profile's bin width).
        g = self.result.geometry()
        tops = grain_tops(self.result, self.s)
        top = int(np.argmax(tops))
        self.assertAlmostEqual(tops[top], g.apex_y_m, delta=1e-12 * g.apex_y_m)
        diameter = self.result.report["dem"]["plate_force_profile"]["bin_width_m"]
        self.assertLessEqual(abs(self.s.position[top, 0] - g.apex_x_m), diameter * (1 + 1e-12))

    def test_scaled_plate_load_integrates_to_the_plate_force_over_R(self):
        g = self.result.geometry()
        x, load, se = self.result.plate_load()
        xs, load_s, se_s = self.result.plate_load(scaled=True)
        np.testing.assert_array_equal(load_s, load)  # only the abscissa changes
        np.testing.assert_array_equal(se_s, se)
        np.testing.assert_allclose(xs * g.half_width_m + g.apex_x_m, x, rtol=0, atol=1e-12 * np.abs(x).max())
        # x' = (x - apex) / R, so dx' = dx / R and sum(load dx') = (sum(load dx)) / R = F / R.
        d = self.result.report["dem"]
        width = d["plate_force_profile"]["bin_width_m"]
        dxs = np.diff(xs)
        np.testing.assert_allclose(dxs, width / g.half_width_m, rtol=1e-9)
        plate_force = d["plate_force_over_weight"] * weight(self.result, self.s)
        self.assertAlmostEqual((load_s * dxs[0]).sum() / (plate_force / g.half_width_m), 1.0, delta=1e-9)
        # The apex lies at x' = 0, inside the plate's bins.
        self.assertLess(xs.min(), 0.0)
        self.assertGreater(xs.max(), 0.0)

    def test_scaled_base_pressure_is_the_same_profile_along_x_over_R(self):
        g = self.result.geometry()
        x, p, se = self.result.base_pressure()
        xs, ps, ses = self.result.base_pressure(scaled=True)
        np.testing.assert_array_equal(ps, p)
        np.testing.assert_array_equal(ses, se)
        np.testing.assert_allclose(xs, (x - g.apex_x_m) / g.half_width_m, rtol=1e-15, atol=0)


def write_json(path, value):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(value, f)


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class GeometryFromOtherReports(unittest.TestCase):
    """Reports other than a whole pile's: an older one without the dip statistic, one whose
    flank has no angle, one without a dem section, and an ensemble's (the mean wedge)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="pilelab_analysis_")
        self.addCleanup(shutil.rmtree, self.dir)
        with open(os.path.join(OUT, "report.json"), encoding="utf-8") as f:
            self.dem = json.load(f)["dem"]

    def run_of(self, report, name="run"):
        write_json(os.path.join(self.dir, name, "report.json"), report)
        return pilelab.load(os.path.join(self.dir, name))

    def test_a_report_without_the_dip_statistic_gives_R_by_its_formula(self):
        dem = copy.deepcopy(self.dem)
        del dem["plate_force_dip"]
        g = self.run_of({"dem": dem}).geometry()
        want = self.dem["plate_force_dip"]["half_width_m"]
        self.assertAlmostEqual(g.half_width_m, want, delta=1e-12 * want)
        self.assertIn("R from height_m", g.source)

    def test_a_flank_without_an_angle_has_no_R_and_no_x_over_R(self):
        dem = copy.deepcopy(self.dem)
        dem["repose_angle_left_deg"] = None
        dem["plate_force_dip"]["half_width_m"] = None
        run = self.run_of({"dem": dem})
        self.assertTrue(math.isnan(run.geometry().half_width_m))
        with self.assertRaises(ValueError) as e:
            run.plate_load(scaled=True)
        self.assertIn("no half-width", str(e.exception))
        x, _, _ = run.plate_load()  # unscaled, still there
        self.assertEqual(len(x), len(self.dem["plate_force_profile"]["x_m"]))

    def test_a_run_without_a_dem_section_is_named(self):
        run = self.run_of({"mesh": {}})
        with self.assertRaises(KeyError) as e:
            run.geometry()
        self.assertIn("no dem section", str(e.exception))
        dem = copy.deepcopy(self.dem)
        dem["apex_x_m"] = "left"
        with self.assertRaises(pilelab.FormatError) as e:
            self.run_of({"dem": dem}, "bad").geometry()
        self.assertIn("dem.apex_x_m", str(e.exception))

    def test_an_ensemble_takes_the_wedge_of_the_members_means(self):
        members = []
        for k, (shift, scale, left, right) in enumerate(((-0.01, 1.0, 30.0, 34.0), (0.02, 1.2, None, 26.0),
                                                          (0.0, 0.8, 36.0, 28.0))):
            dem = copy.deepcopy(self.dem)
            dem.update(apex_x_m=shift, height_m=scale * 0.1, repose_angle_left_deg=left, repose_angle_right_deg=right)
            write_json(os.path.join(self.dir, "ens", f"m{k}", "report.json"), {"dem": dem})
            members.append({"directory": f"m{k}", "seed": k})
        run = self.run_of({"ensemble": {"members": members}}, "ens")
        g = run.geometry()
        self.assertAlmostEqual(g.apex_x_m, 0.01 / 3, delta=1e-15)
        self.assertAlmostEqual(g.apex_y_m, 0.1, delta=1e-15)
        self.assertAlmostEqual(g.repose_angle_left_deg, 33.0, delta=1e-12)  # the member without one left out
        self.assertAlmostEqual(g.repose_angle_right_deg, 88.0 / 3, delta=1e-12)
        feet = 0.1 / math.tan(math.radians(33.0)) + 0.1 / math.tan(math.radians(88.0 / 3))
        self.assertAlmostEqual(2 * g.half_width_m, feet, delta=1e-12)
        x, _, _ = run.plate_load()
        xs, _, _ = run.plate_load(scaled=True)
        np.testing.assert_allclose(xs, (x - g.apex_x_m) / g.half_width_m, rtol=1e-15)
        self.assertEqual([m.geometry().apex_x_m for m in run.members], [-0.01, 0.02, 0.0])


@unittest.skipUnless(OUT and HAVE_PANDAS, "set PILELAB_RUN to a `pilelab run` output directory; needs pandas")
class FrameUnits(unittest.TestCase):
    """A column's name promises its unit: a dataset whose `unit` attribute says otherwise is
    refused, naming the file and the dataset, not tabulated under the wrong name."""

    def test_a_dataset_in_other_units_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "dem.h5")
            shutil.copyfile(os.path.join(OUT, "dem.h5"), path)
            with h5py.File(path, "r+") as f:
                f["snapshots/settled/position"].attrs["unit"] = "mm"
                f["snapshots/settled/contacts/chord"].attrs["unit"] = "mm"
            s = pilelab.DemFile(path).snapshot("settled")
            for frame, field in ((s.to_frame, "/snapshots/settled/position"),
                                 (s.contacts.to_frame, "/snapshots/settled/contacts/chord")):
                with self.assertRaises(pilelab.FormatError) as e:
                    frame()
                message = str(e.exception)
                self.assertTrue(message.startswith(f"{path}: {field}:"), message)
                self.assertIn("'mm'", message)


if __name__ == "__main__":
    unittest.main()
