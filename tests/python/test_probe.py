"""The Python reader's HDF5 probe (python/pilelab/_probe.py): before a file is opened, a child
process reads all of it, so that a file that crashes libhdf5, makes it loop or fails a
Fletcher-32 checksum is a pilelab.FormatError naming the file, not a dead Python process. A
crash is simulated by a child that kills itself with SIGSEGV where it reads a given dataset.

    PYTHONPATH=python PILELAB_RUN=OUT /usr/bin/python3 -m unittest tests/python/test_probe.py
"""
import os
import shutil
import subprocess
import unittest
from unittest import mock

import h5py
import numpy as np

import pilelab
from pilelab import _h5, _probe
from test_damaged import RefusalCase  # noqa: E402  (same folder)

OUT = os.environ.get("PILELAB_RUN", "")
FILES = ("report.json", "dem.h5", "fields.h5", "models.h5", "profiles.csv")

# Put before the probe's own child code: the child dies of SIGSEGV when it reads the data of
# the dataset named by PILELAB_TEST_CRASH_AT, as libhdf5 does on some damaged files.
CRASH_AT = r'''
import os, signal, sys
sys.path[:] = [p for p in sys.argv[3].split("\n") if p] or sys.path
import h5py
_getitem = h5py.Dataset.__getitem__
def _crash_at(self, key):
    if self.name == os.environ["PILELAB_TEST_CRASH_AT"]:
        os.kill(os.getpid(), signal.SIGSEGV)
    return _getitem(self, key)
h5py.Dataset.__getitem__ = _crash_at
'''

PATTERN = np.arange(1, 513, dtype="<f8") * 0.3125 + 1e-3  # doubles whose bytes occur once


def flip_bit(path, data, element, bit):
    """Flips one bit of element `element` of the array data where its bytes lie in the file at
    path (they must occur there exactly once)."""
    with open(path, "rb") as f:
        raw = bytearray(f.read())
    needle = np.ascontiguousarray(data).tobytes()
    at = raw.find(needle)
    assert at >= 0 and raw.find(needle, at + 1) < 0, "the data's bytes must occur once in the file"
    raw[at + element * data.itemsize + bit // 8] ^= 1 << (bit % 8)
    with open(path, "wb") as f:
        f.write(raw)


def write_checksummed(path, fmt="pilelab-dem"):
    """A small file as the C++ writer now stores them: datasets in chunks with Fletcher-32."""
    with h5py.File(path, "w") as f:
        f.attrs["format"] = fmt
        f.attrs["format_version"] = 1
        d = f.create_dataset("data/pattern", data=PATTERN, fletcher32=True, chunks=True)
        d.attrs["unit"] = "m"


def copy_checksummed(source, target):
    """source rewritten into target with every non-scalar dataset chunked and checksummed."""
    with h5py.File(source, "r") as src, h5py.File(target, "w") as dst:
        dst.attrs.update(dict(src.attrs))

        def copy(name, obj):
            if isinstance(obj, h5py.Group):
                dst.create_group(name).attrs.update(dict(obj.attrs))
                return
            data = obj[()]
            checksummed = obj.ndim > 0 and obj.size > 0
            d = dst.create_dataset(name, data=data, dtype=obj.dtype,
                                   **({"chunks": True, "fletcher32": True} if checksummed else {}))
            d.attrs.update(dict(obj.attrs))

        src.visititems(copy)


class ProbeCase(RefusalCase):
    """RefusalCase's directory and assertRefused, with the probe's cache emptied and the probe on."""

    def setUp(self):
        super().setUp()
        _probe._readable.clear()
        self.addCleanup(_probe._readable.clear)
        # The probe on, whatever the caller's environment says.
        patch = mock.patch.dict(os.environ, {"PILELAB_HDF5_PROBE": "1"})
        patch.start()
        self.addCleanup(patch.stop)
        self.file = os.path.join(self.dir, "pattern.h5")
        write_checksummed(self.file)

    def open(self, path=None):
        with _h5.open_file(path or self.file, "pilelab-dem") as f:
            return f["data/pattern"][()]


class Crashes(ProbeCase):
    def test_a_child_that_crashes_refuses_the_file_naming_where(self):
        with mock.patch.object(_probe, "CHILD_CODE", CRASH_AT + _probe.CHILD_CODE), \
             mock.patch.dict(os.environ, {"PILELAB_TEST_CRASH_AT": "/data/pattern"}):
            self.assertRefused(self.open, self.file, "HDF5 crashed reading this file", "signal 11, SIGSEGV",
                               "at /data/pattern (its data)", "a damaged file")
            self.assertEqual(_probe._readable, set())  # refused again next time, not cached
            self.assertRefused(self.open, self.file, "crashed")

    def test_a_crash_names_the_last_place_the_child_reported(self):
        code = "import os, signal; print('>\\t/\\tthe file', flush=True); os.kill(os.getpid(), signal.SIGSEGV)"
        with mock.patch.object(_probe, "CHILD_CODE", code):
            self.assertRefused(self.open, self.file, "crashed", "signal 11", "at / (the file)")

    def test_a_child_killed_before_it_reached_the_file_is_no_verdict(self):
        # Killed before its first report (starting Python, importing h5py): not the file's doing.
        code = "import os, signal; os.kill(os.getpid(), signal.SIGKILL)"
        with mock.patch.object(_probe, "CHILD_CODE", code):
            np.testing.assert_array_equal(self.open(), PATTERN)
        self.assertEqual(_probe._readable, set())  # nor taken as read

    def test_a_child_that_hangs_is_refused_after_the_limit(self):
        code = "import time; print('>\\t/data/pattern\\tits data', flush=True); time.sleep(60)"
        with mock.patch.object(_probe, "CHILD_CODE", code), \
             mock.patch.dict(os.environ, {"PILELAB_HDF5_PROBE_LIMIT_S": "1"}):
            self.assertRefused(self.open, self.file, "did not finish reading this file within 1 s",
                               "at /data/pattern (its data)")

    def test_the_probe_can_be_turned_off(self):
        with mock.patch.object(_probe, "CHILD_CODE", CRASH_AT + _probe.CHILD_CODE), \
             mock.patch.dict(os.environ, {"PILELAB_TEST_CRASH_AT": "/data/pattern",
                                          "PILELAB_HDF5_PROBE": "0"}), \
             mock.patch.object(_probe.subprocess, "run", wraps=subprocess.run) as run:
            np.testing.assert_array_equal(self.open(), PATTERN)
            self.assertEqual(run.call_count, 0)

    @unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
    def test_a_run_whose_dem_file_crashes_hdf5_is_refused_on_load(self):
        for name in FILES:
            shutil.copy(os.path.join(OUT, name), self.dir)
        path = os.path.join(self.dir, "dem.h5")
        run = pilelab.load(self.dir)
        with mock.patch.object(_probe, "CHILD_CODE", CRASH_AT + _probe.CHILD_CODE), \
             mock.patch.dict(os.environ, {"PILELAB_TEST_CRASH_AT": "/snapshots/settled/position"}):
            self.assertRefused(lambda: run.dem.snapshot("settled"), path, "HDF5 crashed reading this file",
                               "at /snapshots/settled/position (its data)")
        self.assertIn("stress_yy", run.fields)  # the run's other files still read


class Checksums(ProbeCase):
    def test_the_undamaged_file_reads(self):
        np.testing.assert_array_equal(self.open(), PATTERN)

    def test_a_flipped_bit_in_checksummed_data_names_the_dataset(self):
        flip_bit(self.file, PATTERN, element=200, bit=3)  # a low mantissa bit: still a finite number
        self.assertRefused(self.open, self.file, "/data/pattern: its data cannot be read",
                           "Fletcher32 checksum", "a damaged file")

    @unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
    def test_a_flipped_bit_in_a_runs_positions_is_refused_on_load(self):
        for name in FILES:
            shutil.copy(os.path.join(OUT, name), self.dir)
        path = os.path.join(self.dir, "dem.h5")
        copy_checksummed(os.path.join(OUT, "dem.h5"), path)
        with h5py.File(path, "r") as f:
            position = f["snapshots/settled/position"][()]
        self.assertEqual(len(pilelab.load(self.dir).dem.snapshot("settled")), len(position))  # whole, it reads
        _probe._readable.clear()
        flip_bit(path, position, element=7, bit=1)
        run = pilelab.load(self.dir)
        self.assertRefused(lambda: run.dem.snapshot("settled"), path, "/snapshots/settled/position",
                           "its data cannot be read", "Fletcher32")


class Cache(ProbeCase):
    def test_one_child_per_file_version(self):
        with mock.patch.object(_probe.subprocess, "run", wraps=subprocess.run) as run:
            for _ in range(3):
                np.testing.assert_array_equal(self.open(), PATTERN)
            self.assertEqual(run.call_count, 1)
            st = os.stat(self.file)
            os.utime(self.file, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))  # another version
            self.open()
            self.assertEqual(run.call_count, 2)

    @unittest.skipUnless(OUT, "set PILELAB_RUN to a `pilelab run` output directory")
    def test_a_run_probes_each_file_once(self):
        for name in FILES:
            shutil.copy(os.path.join(OUT, name), self.dir)
        with mock.patch.object(_probe.subprocess, "run", wraps=subprocess.run) as run:
            result = pilelab.load(self.dir)
            result.dem.snapshot("settled")
            result.dem.snapshot("settled")
            result.fields, result.models
            again = pilelab.load(self.dir)
            again.dem.snapshot("settled")
            again.fields, again.models
            probed = sorted(os.path.basename(c.args[0][3]) for c in run.call_args_list)
        self.assertEqual(probed, ["dem.h5", "fields.h5", "models.h5"])

    def test_files_that_do_not_open_keep_their_usual_message(self):
        path = os.path.join(self.dir, "not.h5")
        with open(path, "wb") as f:
            f.write(b"not HDF5 at all" * 100)
        self.assertRefused(lambda: self.open(path), path, "/: cannot open as HDF5")
        missing = os.path.join(self.dir, "missing.h5")
        self.assertRefused(lambda: self.open(missing), missing, "cannot open as HDF5")


if __name__ == "__main__":
    unittest.main()
