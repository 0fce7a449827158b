"""Two pictures of a pilelab run rendered by ParaView, headless:

    xvfb-run -a pvpython scripts/paraview_pictures.py OUT

OUT/figures/paraview_force_chains.png: the grains of the last frame coloured by their pressure,
the contact network on top as tubes whose radius follows the normal force.
OUT/figures/paraview_stress.png: the coarse-grained pressure on the mesh (fields.vtu) with the
major compressive stress axes as lines of one length on a regular grid (the colour gives the
magnitude).
Either picture is skipped (with a line saying so) when its files are missing. For an ensemble
the force chains are those of its first member.
"""
import json
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # pvpython may not add it
from figures_dir import probe_figures_dir  # noqa: E402
from paraview.simple import (CellDatatoPointData, ColorBy, ExtractSurface, GetActiveViewOrCreate, GetSources, Hide, GetColorTransferFunction, GetScalarBar,
                             Glyph, ResampleToImage, SaveScreenshot, Show, Threshold, Tube,
                             XMLUnstructuredGridReader)


def last_frame(directory):
    """The grains and contacts files of the last frame listed in directory/dem.pvd."""
    pvd = os.path.join(directory, "dem.pvd")
    if not os.path.exists(pvd):
        return None, None
    frames = {}
    for d in ET.parse(pvd).getroot().iter("DataSet"):
        frames.setdefault(float(d.get("timestep")), {})[d.get("part")] = os.path.join(directory, d.get("file"))
    last = frames[max(frames)]
    return last.get("0"), last.get("1")


def dark_scalar_bar(array, view, title):
    """The colour legend in black, readable on the white background."""
    bar = GetScalarBar(GetColorTransferFunction(array), view)
    bar.Title, bar.ComponentTitle = title, ""
    bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]


def view_2d(size):
    view = GetActiveViewOrCreate("RenderView")
    for source in GetSources().values():  # nothing of the last picture shows
        Hide(source, view)
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.CameraParallelProjection = 1
    view.InteractionMode = "2D"
    return view


def frame_camera(view, source, size):
    """Looks down z at the bounds of source, filling the picture."""
    source.UpdatePipeline()
    x0, x1, y0, y1, _, _ = source.GetDataInformation().GetBounds()
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    view.CameraFocalPoint = [cx, cy, 0.0]
    view.CameraPosition = [cx, cy, 10.0]
    view.CameraViewUp = [0, 1, 0]
    aspect = size[0] / size[1]
    view.CameraParallelScale = 0.55 * max(y1 - y0, (x1 - x0) / aspect)


def cannot_write(path, reason):
    """A full disk or a read-only folder: the file and the reason, exit code 2 (a bad environment,
    as the C++ stages and figures.py report it), no traceback."""
    print(f"paraview_pictures.py: {path}: cannot write: {reason}", file=sys.stderr)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(2)  # not sys.exit: ParaView's own clean-up crashed (SIGSEGV) after a failed write


def prepare_figures_dir(out):
    """OUT/figures made and probed before ParaView renders anything (scripts/figures_dir.py)."""
    directory, reason = probe_figures_dir(out)
    if reason:
        cannot_write(directory, reason)


def complete_png(path):
    """Whether path is a whole PNG: its signature first and its IEND chunk last. ParaView does
    not report a failed write (a full disk leaves a short file or none)."""
    try:
        with open(path, "rb") as f:
            head = f.read(8)
            f.seek(-12, os.SEEK_END)
            tail = f.read(12)
    except OSError:
        return False
    return head == b"\x89PNG\r\n\x1a\n" and tail[4:8] == b"IEND"


def save(view, framed, png, size=(1800, 700)):
    """Frames the view on framed and writes png: under a temporary name of this process,
    checked whole, then renamed, so that a good picture is never replaced by a broken one."""
    frame_camera(view, framed, size)
    tmp = png + f".tmp.{os.getpid()}.png"
    SaveScreenshot(tmp, view, ImageResolution=list(size))
    if not complete_png(tmp):
        if os.path.exists(tmp):
            os.remove(tmp)
        cannot_write(png, "ParaView wrote no complete PNG (is the disk full?); the previous picture is kept")
    try:
        os.replace(tmp, png)
    except OSError as e:
        os.remove(tmp)
        cannot_write(png, e.strerror or e)
    print("wrote", png)
    return True


def force_chains(out, directory, png):
    grains_file, contacts_file = last_frame(directory)
    if not grains_file or not contacts_file:
        print("paraview: no dem.pvd frames; no force-chain picture")
        return False
    view = view_2d([1800, 700])
    bodies = XMLUnstructuredGridReader(FileName=[grains_file])
    # The grains only (the plate and the funnel are far wider than the pile).
    grains = Threshold(Input=bodies)
    grains.Scalars = ["CELLS", "is_wall"]
    try:
        grains.LowerThreshold, grains.UpperThreshold = 0, 0
    except AttributeError:  # ParaView before 5.10
        grains.ThresholdRange = [0, 0]
    g = Show(grains, view)
    ColorBy(g, ("CELLS", "pressure"))
    lut = GetColorTransferFunction("pressure")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    g.SetScalarBarVisibility(view, True)
    dark_scalar_bar("pressure", view, "grain pressure [N/m]")
    # A Tube needs lines as polydata with point scalars: surface first, then cell to point data
    # (feeding the unstructured grid straight to Tube is what crashed).
    contacts = XMLUnstructuredGridReader(FileName=[contacts_file])
    lines = CellDatatoPointData(Input=ExtractSurface(Input=contacts))
    tubes = Tube(Input=lines)
    tubes.Scalars = ["POINTS", "normal_force"]
    tubes.VaryRadius = "By Scalar"
    tubes.Radius = 0.00025
    tubes.RadiusFactor = 6.0
    t = Show(tubes, view)
    t.ColorArrayName = [None, ""]
    t.AmbientColor = t.DiffuseColor = [0.1, 0.1, 0.1]
    return save(view, grains, png)


def stress_field(out, png):
    fields = os.path.join(out, "fields.vtu")
    if not os.path.exists(fields):
        print("paraview: no fields.vtu; no stress picture")
        return False
    view = view_2d([1800, 700])
    mesh = XMLUnstructuredGridReader(FileName=[fields])
    m = Show(mesh, view)
    ColorBy(m, ("POINTS", "pressure"))
    GetColorTransferFunction("pressure").ApplyPreset("Viridis (matplotlib)", True)
    m.SetScalarBarVisibility(view, True)
    dark_scalar_bar("pressure", view, "pressure [N/m]")
    # The axes on a regular grid of about 45 columns, each a line of one length (the colour
    # beneath gives the magnitude): scaled by the principal value, the axes near the surface,
    # where the stress vanishes, would not show, and glyphs on the mesh nodes crowd where the
    # mesh is fine.
    mesh.UpdatePipeline()
    x0, x1, y0, y1, _, _ = mesh.GetDataInformation().GetBounds()
    columns = 45
    spacing = (x1 - x0) / columns
    grid = ResampleToImage(Input=mesh)
    grid.UseInputBounds = 0
    # Half a spacing inside the bounds, so that no line crosses the base.
    grid.SamplingBounds = [x0 + 0.5 * spacing, x1 - 0.5 * spacing, y0 + 0.5 * spacing, y1, 0.0, 0.0]
    grid.SamplingDimensions = [columns, max(2, int(round((y1 - y0) / spacing))), 1]
    inside = Threshold(Input=grid)  # grid points outside the pile have no data
    inside.Scalars = ["POINTS", "vtkValidPointMask"]
    try:
        inside.LowerThreshold, inside.UpperThreshold = 1, 1
    except AttributeError:  # ParaView before 5.10
        inside.ThresholdRange = [1, 1]
    arrows = Glyph(Input=inside, GlyphType="Line")
    arrows.OrientationArray = ["POINTS", "stress_major_axis"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 0.8 * spacing
    arrows.GlyphMode = "All Points"
    arrows.GlyphTransform.Translate = [-0.5, 0.0, 0.0]  # a line centred on its point: an axis
    a = Show(arrows, view)
    a.Position = [0.0, 0.0, 1e-3 * (x1 - x0)]  # in front of the surface, which they share z = 0 with
    a.ColorArrayName = [None, ""]
    a.AmbientColor = a.DiffuseColor = [0.1, 0.1, 0.1]
    return save(view, mesh, png)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: xvfb-run -a pvpython scripts/paraview_pictures.py OUT")
    out = sys.argv[1]
    prepare_figures_dir(out)
    directory = out
    report = os.path.join(out, "report.json")
    if not os.path.exists(os.path.join(out, "dem.pvd")) and os.path.exists(report):
        members = json.load(open(report)).get("ensemble", {}).get("members", [])
        if members:
            directory = os.path.join(out, members[0]["directory"])
    force_chains(out, directory, os.path.join(out, "figures", "paraview_force_chains.png"))
    stress_field(out, os.path.join(out, "figures", "paraview_stress.png"))


if __name__ == "__main__":
    main()
