"""Read pilelab results in Python: one call loads a run directory.

    import pilelab
    run = pilelab.load("out/quick")
    run.report["dem"]["repose_angle_left_deg"]
    s = run.dem.snapshot("settled")          # grains and contacts of one instant
    s.position, s.units["position"]          # (n, 2) array, "m"
    s.contacts.grain_b                       # rows into the snapshot's grain arrays (-1: a wall)
    run.fields["stress_yy"], run.fields.stderr("stress_yy")
    run.profiles("dem", "sigma_yy")          # the horizontal cuts of profiles.csv
    run.geometry(), run.plate_load(scaled=True)   # apex and R; the plate's load along (x - apex) / R
    s.to_frame(), s.contacts.to_frame()      # pandas DataFrames, SI units in the column names
    s.coordination_number(walls=False)       # 2 C_gg / N
    [m.dem.snapshot().position for m in run.members]   # an ensemble's piles

Pure Python on numpy and h5py (Debian's python3-numpy and python3-h5py). Files are opened only
when a property is first used, and every string comes back as `str`. Units: every array has
its unit in the `units` mapping of the object that holds it (SI, as docs/FORMAT.md lists them).

Files are checked as the C++ readers check them (format and format_version, shapes, index
ranges, finite numbers): a missing, damaged or truncated one is a FormatError (a ValueError)
whose message starts with the file's path and names the field and what was expected.
"""
from pilelab._check import FormatError
from pilelab.dem import Contacts, DemFile, Snapshot
from pilelab.fields import Fields, Models
from pilelab.run import Member, PileGeometry, Run, load

__all__ = ["load", "FormatError", "Run", "Member", "PileGeometry", "DemFile", "Snapshot", "Contacts", "Fields", "Models"]
