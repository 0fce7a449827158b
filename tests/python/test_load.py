"""The Python reader on the tiny pipeline's outputs: shapes and units as docs/FORMAT.md gives
them, contact rows that point at the right grains, and quantities derived in Python that must
equal what the C++ wrote (Newton's third law, the mesh area, the coarse profile).

    PYTHONPATH=python /usr/bin/python3 -m unittest tests/python/test_load.py   (PILELAB_RUN=OUT)
"""
import os
import unittest

import numpy as np

import pilelab

OUT = os.environ.get("PILELAB_RUN", "")


@unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
class LoadTinyPipeline(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.result = pilelab.load(OUT)  # a missing directory is an error, not a skip

    def test_report_and_scene(self):
        self.assertIn("dem", self.result.report)
        self.assertIsInstance(self.result.scene_text, str)
        self.assertEqual(self.result.scene["scene"]["name"], "tiny")
        self.assertEqual(self.result.members, [])

    def test_snapshot_shapes_and_units(self):
        s = self.result.dem.snapshot("settled")
        n = len(s)
        self.assertEqual(n, self.result.report["dem"]["particles"])
        for name, shape, unit in (("position", (n, 2), "m"), ("velocity", (n, 2), "m/s"), ("angle", (n,), "rad"),
                                  ("angular_velocity", (n,), "rad/s"), ("contact_force", (n, 2), "N")):
            self.assertEqual(getattr(s, name).shape, shape, name)
            self.assertEqual(s.units[name], unit, name)
        c = s.contacts
        self.assertEqual(c.point.shape, (len(c), 2))
        self.assertEqual(c.units["normal_force"], "N")
        self.assertEqual(c.units["overlap_area"], "m^2")
        self.assertIsInstance(self.result.dem.snapshot_names[0], str)
        self.assertEqual(len(s.polygons()), n)

    def test_contact_rows_name_the_bodies_of_the_pair(self):
        s = self.result.dem.snapshot("settled")
        c = s.contacts
        for rows, column in ((c.grain_a, 0), (c.grain_b, 1)):
            grains = rows >= 0
            np.testing.assert_array_equal(s.body[rows[grains]], c.pair[grains, column])
            # A row of -1 is a wall: bodies 0 .. w-1.
            self.assertTrue(np.all(c.pair[~grains, column] < self.result.dem.wall_count))
        self.assertTrue(np.all(c.grain_b >= 0), "b is never a wall (walls have the lower indices)")

    def test_plate_load_integrates_to_the_plate_force_the_report_gives(self):
        # The profile that plate_load() returns integrates to the grain-plate contacts' vertical
        # force, which the report gives over the weight; both from the settled snapshot.
        x, load, stderr = self.result.plate_load()
        d = self.result.report["dem"]
        width = d["plate_force_profile"]["bin_width_m"]
        s = self.result.dem.snapshot("settled")
        weight = self.result.dem.bodies["mass"][s.body].sum() * s.gravity_m_per_s2
        on_plate = s.contacts.pair[:, 0] == 0
        self.assertAlmostEqual(load.sum() * width / weight, d["plate_force_over_weight"], delta=1e-12)
        self.assertAlmostEqual(s.contacts.force[on_plate, 1].sum() / weight, d["plate_force_over_weight"], delta=1e-12)
        self.assertEqual(x.shape, load.shape)
        np.testing.assert_array_equal(stderr, 0.0)  # one pile: no spread

    def test_contact_forces_sum_to_the_walls_force(self):
        # Newton's third law: the grains' contact forces between themselves cancel, so the sum of
        # every grain's contact_force (written by the C++) equals the force of the walls on the
        # grains, summed here from the contact table. Round-off only.
        s = self.result.dem.snapshot("settled")
        c = s.contacts
        on_walls = c.grain_a < 0
        walls_on_grains = c.force[on_walls].sum(axis=0)
        total = s.contact_force.sum(axis=0)
        scale = np.abs(c.force).sum()
        np.testing.assert_allclose(total, walls_on_grains, atol=1e-12 * scale)
        # Where the pile fell quiet, the plate carries its weight (what remains is the mass times
        # the mean acceleration of a pile whose kinetic energy is below the threshold: small).
        if self.result.report["dem"]["settling"]["settled"]["reached_threshold"]:
            mass = self.result.dem.bodies["mass"][s.body].sum()
            self.assertAlmostEqual(walls_on_grains[1] / (mass * s.gravity_m_per_s2), 1.0, delta=0.05)

    def test_grain_stress_is_symmetric_and_sums_to_the_contact_moments(self):
        # sum_g A_g sigma_g = sum over grain-grain contacts of l (x) f (the branch vector between
        # the centres) plus the wall contacts' arms: checked against a direct sum.
        s = self.result.dem.snapshot("settled")
        sigma = s.grain_stress()
        np.testing.assert_allclose(sigma, np.transpose(sigma, (0, 2, 1)), atol=0)
        total = (sigma * s.area()[:, None, None]).sum(axis=0)
        c = s.contacts
        direct = np.zeros((2, 2))
        for k in range(len(c)):
            f = c.force[k]
            b = c.grain_b[k]
            direct += np.outer(c.point[k] - s.position[b], f)
            a = c.grain_a[k]
            if a >= 0:
                direct += np.outer(c.point[k] - s.position[a], -f)
        direct = 0.5 * (direct + direct.T)
        np.testing.assert_allclose(total, direct, rtol=1e-12, atol=1e-15 * np.abs(direct).max())
        self.assertEqual(s.grain_pressure().shape, (len(s),))

    def test_fields_mesh_and_units(self):
        f = self.result.fields
        self.assertEqual(f.location, "nodes")
        self.assertEqual(f.points.shape, f.nodes.shape)
        self.assertEqual(f.units["stress_yy"], "N/m")
        self.assertEqual(f["stress_yy"].shape, (len(f.points),))
        self.assertTrue(np.all(f.stderr("stress_yy") == 0), "one pile: no spread")
        # The mesh area, summed here, equals the mesh stage's report.
        p = f.nodes[f.triangles]
        area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])).sum()
        self.assertAlmostEqual(area, self.result.report["mesh"]["area_m2"], delta=1e-12 * area)

    def test_models_and_profiles(self):
        m = self.result.models
        self.assertIn("elastic", m.names)
        self.assertNotIn("mesh", m.names)
        # The models' vertices are the mesh's nodes and their triangles the mesh's triangles.
        self.assertEqual(m.vertex_count, self.result.report["mesh"]["nodes"])
        self.assertEqual(m.triangles.shape, (self.result.report["mesh"]["triangles"], 3))
        self.assertEqual(len(m.points("elastic")), m.vertex_count + len(m.triangles))
        self.assertEqual(m.units["elastic"]["points"], "m")
        pairs = self.result.profiles()
        self.assertIn(("dem", "sigma_yy"), pairs)
        x, v, e = self.result.base_pressure("dem")
        self.assertTrue(np.all(np.diff(x) > 0))
        self.assertTrue(np.all(np.isfinite(v)))


    def test_profiles_frame_when_pandas_is_there(self):
        try:
            import pandas  # noqa: F401
        except ImportError:
            self.skipTest("pandas is not installed")
        frame = self.result.profiles_frame()
        rows = sum(len(v) for pair in self.result.profiles() for v in self.result.profiles(*pair).values())
        self.assertEqual(len(frame), rows)


if __name__ == "__main__":
    unittest.main()


class LoadFailsClearly(unittest.TestCase):
    """An empty folder, a damaged report: errors that name the file, not raw exceptions later."""

    def test_an_empty_folder_is_refused_naming_it(self):
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(FileNotFoundError) as e:
                pilelab.load(d)
            self.assertIn(d, str(e.exception))
            self.assertIn("no run's outputs here", str(e.exception))

    def test_a_truncated_report_names_the_file(self):
        import tempfile
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "report.json")
            with open(path, "w", encoding="utf-8") as f:
                f.write('{"dem": {"height_m": 0.3')  # a run killed while writing it (or a damaged copy)
            run = pilelab.load(d)
            with self.assertRaises(ValueError) as e:
                run.report
            self.assertIn(path, str(e.exception))
            self.assertIn("not valid JSON", str(e.exception))
