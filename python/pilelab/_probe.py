"""A damaged HDF5 file can crash libhdf5 itself (a segmentation fault takes the Python process
with it), or make it loop. So before a file is opened, a child Python process reads all of it:
every object, every attribute, every dataset in full (which also verifies the Fletcher-32
checksums the C++ writer stores). A child killed by a signal, or still reading after the time
limit, or refused by h5py, makes the file a FormatError naming it; a file read whole is not read
again by a child in this process until it changes (device, inode, size, modification time).
common/hdf5_probe.cpp does the same for the C++ readers.

Environment: PILELAB_HDF5_PROBE=0 skips the probe (faster, but a damaged file may then crash
the process); PILELAB_HDF5_PROBE_LIMIT_S sets the time limit in seconds (60 by default)."""
import os
import signal
import subprocess
import sys

from pilelab._check import FormatError, fail

DEFAULT_LIMIT_S = 60

# The child's program: argv = [path, limit in seconds, the parent's sys.path joined by newlines].
# Before each part it prints "> object<TAB>part", flushed, so that the parent can name where it
# crashed; a part h5py refuses is the line "! object<TAB>part<TAB>error" and exit status 1.
# Exit 2: the file does not open (the reader's own open names that); 3: no h5py to read with.
# A module variable, so that a test can put a child that crashes in its place.
CHILD_CODE = r'''
import signal, sys
path, limit = sys.argv[1], float(sys.argv[2])
sys.path[:] = [p for p in sys.argv[3].split("\n") if p] or sys.path
signal.signal(signal.SIGALRM, signal.SIG_DFL)
signal.alarm(int(limit) + 2)  # a child whose parent died still ends
try:
    import resource
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))  # a crash here is expected: no core file
except Exception:
    pass


def line(*fields):
    sys.stdout.write("\t".join(" ".join(str(f).split()) for f in fields) + "\n")
    sys.stdout.flush()


try:
    import h5py
except Exception as e:
    line("?", f"cannot import h5py: {e}")
    sys.exit(3)

where = ["/", "the file"]


def at(name, part):
    where[:] = [name, part]
    line(">", name, part)


def read_whole(name, obj):
    at(name, "its attribute names")
    for key in list(obj.attrs):
        at(name, f"attribute {key}")
        obj.attrs[key]
    if isinstance(obj, h5py.Dataset):
        at(name, "its data")
        obj[()]


def visit(name):
    at("/" + name, "the object")
    read_whole("/" + name, f[name])


at("/", "the file")
try:
    f = h5py.File(path, "r")
except Exception as e:
    line("!", "/", "the file", f"{type(e).__name__}: {e}")
    sys.exit(2)
try:
    read_whole("/", f)
    at("/", "its links")
    f.visit(visit)
except Exception as e:
    line("!", where[0], where[1], f"{type(e).__name__}: {e}")
    sys.exit(1)
line("=")
'''

_readable = set()  # (path, device, inode, size, mtime_ns) of files read whole by a child


def enabled():
    return os.environ.get("PILELAB_HDF5_PROBE", "1").strip() != "0"


def limit_s():
    try:
        return max(1.0, float(os.environ.get("PILELAB_HDF5_PROBE_LIMIT_S", DEFAULT_LIMIT_S)))
    except ValueError:
        return float(DEFAULT_LIMIT_S)


def command(path, limit):
    return [sys.executable, "-c", CHILD_CODE, path, f"{limit:g}", "\n".join(sys.path)]


def _lines(output):
    if not output:
        return []
    return [text.split("\t") for text in output.decode("utf-8", "replace").splitlines()]


def _last_place(lines):
    """' at OBJECT (PART)' from the child's last progress line, or '' when it printed none."""
    places = [fields for fields in lines if fields[0] == ">" and len(fields) >= 3]
    return f" at {places[-1][1]} ({places[-1][2]})" if places else ""


def _signal_name(number):
    try:
        return signal.Signals(number).name
    except ValueError:
        return "unknown signal"


def probe(path):
    """Refuses path (a FormatError naming it) if a child process cannot read every part of it;
    returns quietly when it reads, or when no verdict is possible (no such file, no process to
    spare, no h5py in the child), leaving the reader's own open and checks to speak."""
    if not enabled():
        return
    path = os.fspath(path)
    try:
        st = os.stat(path)
    except OSError:
        return  # the open that follows names the problem
    version = (path, st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)
    if version in _readable:
        return
    limit = limit_s()
    try:
        done = subprocess.run(command(path, limit), timeout=limit, capture_output=True, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired as e:
        raise FormatError(f"{path}: HDF5 did not finish reading this file within {limit:g} s"
                          f"{_last_place(_lines(e.output))}; a damaged file can make it loop") from None
    except OSError:
        return  # no process to spare: the file is read as it is
    lines = _lines(done.stdout)
    code = done.returncode
    if code == 0 and lines and lines[-1] == ["="]:
        _readable.add(version)
        return
    if code < 0:
        number = -code
        if number == signal.SIGALRM:  # the child's own limit
            raise FormatError(f"{path}: HDF5 did not finish reading this file within {limit:g} s"
                              f"{_last_place(lines)}; a damaged file can make it loop")
        place = _last_place(lines)
        if not place:
            return  # killed before it reached the file (by someone else): no verdict
        raise FormatError(f"{path}: HDF5 crashed reading this file (signal {number}, {_signal_name(number)},"
                          f"{place}); a damaged file")
    if code in (2, 3):
        return  # the file does not open (open_file says so), or the child has no h5py
    failures = [fields for fields in lines if fields[0] == "!" and len(fields) >= 4]
    if failures:
        _, name, part, error = failures[-1][:4]
        fail(path, name, f"{part} cannot be read ({error}); a damaged file")
    stderr = done.stderr.decode("utf-8", "replace").strip().splitlines()
    raise FormatError(f"{path}: HDF5 cannot read every part of this file (reading it in a child process ended "
                      f"with status {code}{': ' + stderr[-1] if stderr else ''}); a damaged file?")
