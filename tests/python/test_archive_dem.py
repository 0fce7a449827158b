"""scripts/archive_dem.py on the tiny pipeline's dem.h5: the archive is a dem.h5 that pilelab
reads as it is (here with every array converted, however small), and coarse-graining it on the same mesh gives the original's fields to single
precision. Single precision rounds each stored contact value by at most 2^-24 (6e-8) of itself;
a field is a sum of such terms, so its error stays within a small multiple of that times the
sum of the terms' magnitudes: 1e-6 of it is asserted. For a diagonal component that sum is the
field's largest value (the terms share a sign). An off-diagonal component cancels: for the
fabric its terms are bounded by the diagonal ones (|n_x n_y| <= (n_x^2 + n_y^2) / 2), so its
scale is the largest xx + yy; for the stress, whose terms f_x r_y are not so bounded, the same
scale is taken as the size of the terms (a pile's contact forces lie close to their branch
vectors), not as a proof. The gravity change of the stress is a difference of two such sums:
its scale is the stress's own. Positions and angles are kept exactly, so the
displacements (their differences) must agree to the last bit.

    PILELAB_RUN=OUT PILELAB_BIN=build/apps/pilelab /usr/bin/python3 -m unittest tests/python/test_archive_dem.py
"""
import os
import subprocess
import tempfile
import unittest

import h5py
import numpy as np

OUT = os.environ.get("PILELAB_RUN", "")
BIN = os.environ.get("PILELAB_BIN", "")
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@unittest.skipUnless(OUT and BIN, "set PILELAB_RUN (a `pilelab run` output) and PILELAB_BIN (the pilelab program)")
class ArchiveRoundTrip(unittest.TestCase):
    def coarse(self, dem, mesh, out):
        scene = os.path.join(out, "scene.toml")
        with open(scene, "w") as f:
            f.write(f'[coarse]\ndem_files = ["{dem}"]\nmesh_file = "{mesh}"\nrve_radius_m = 0.012\n')
        subprocess.run([BIN, "coarse", scene, "-o", out], check=True, stdout=subprocess.DEVNULL,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
        return h5py.File(os.path.join(out, "fields.h5"), "r")

    def test_archived_pile_gives_the_same_fields(self):
        with tempfile.TemporaryDirectory() as tmp:
            archive = os.path.join(tmp, "dem.h5")
            subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "archive_dem.py"),
                            os.path.join(OUT, "dem.h5"), archive, "--min-size", "1"], check=True)
            mesh = os.path.join(OUT, "pile.msh")
            os.makedirs(os.path.join(tmp, "a"))
            os.makedirs(os.path.join(tmp, "b"))
            original = self.coarse(os.path.join(OUT, "dem.h5"), mesh, os.path.join(tmp, "a"))
            archived = self.coarse(archive, mesh, os.path.join(tmp, "b"))
            for q in ("stress_xx", "stress_yy", "stress_xy", "fabric_xx", "fabric_xy", "volume_fraction",
                      "coordination", "stress_change_yy"):
                a, b = original["fields/" + q][()], archived["fields/" + q][()]
                np.testing.assert_array_equal(np.isfinite(a), np.isfinite(b), q)
                ok = np.isfinite(a)
                self.assertTrue(ok.any(), q)
                if q == "stress_change_yy":
                    scale = np.abs(original["fields/stress_yy"][()][ok]).max()
                elif q.endswith("_xy"):
                    base = q[:-3]
                    diagonal = np.abs(original["fields/" + base + "_xx"][()]) + np.abs(original["fields/" + base + "_yy"][()])
                    scale = diagonal[ok].max()
                else:
                    scale = np.abs(a[ok]).max()
                self.assertLessEqual(np.abs(a[ok] - b[ok]).max(), 1e-6 * scale, q)
            for q in ("displacement_x", "displacement_y", "strain_xx", "strain_yy"):
                a, b = original["fields/" + q][()], archived["fields/" + q][()]
                np.testing.assert_array_equal(a, b, q)
            with h5py.File(archive, "r") as f:  # every array went through the conversion
                self.assertEqual(f["snapshots/settled/contacts/normal_force"].dtype, np.float32)
                self.assertEqual(f["snapshots/settled/position"].dtype, np.float64)


if __name__ == "__main__":
    unittest.main()
