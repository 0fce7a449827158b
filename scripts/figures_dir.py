"""OUT/figures for the figure scripts (figures.py, paraview_pictures.py): made and probed before
anything is drawn, as the C++ stages probe their folders, so that a full disk or a read-only
folder is found before minutes of drawing, not after."""
import os


def probe_figures_dir(out):
    """Makes OUT/figures and writes, syncs and removes a 4 KiB probe file in it. Returns
    (directory, None) when it can be written, else (directory, the system's reason)."""
    directory = os.path.join(out, "figures")
    probe = os.path.join(directory, f".probe.tmp.{os.getpid()}")
    try:
        os.makedirs(directory, exist_ok=True)
        with open(probe, "wb") as f:
            f.write(b"\0" * 4096)
            f.flush()
            os.fsync(f.fileno())
        os.remove(probe)
        return directory, None
    except OSError as e:
        if os.path.exists(probe):
            os.remove(probe)
        return directory, e.strerror or str(e)
