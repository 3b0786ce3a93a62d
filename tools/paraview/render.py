"""Opens a wetbounce run's ParaView output with ParaView itself (pvbatch), checks what ParaView
reads against trajectories.csv, and renders one frame offscreen to a PNG.

    pvbatch tools/paraview/render.py OUT_DIR SCENE_STEM PNG [TIME]

OUT_DIR is a run's folder written with `--formats vtk,csv`; TIME (s, default: the last frame)
must be one of its frame times. Checks, at that time and at the first frame:
- ParaView's time steps are the CSV's frame times;
- the point count is the CSV's row count;
- each particle's position and velocity (and spin, in a scene with rotation) as ParaView reads
  them are the CSV's, bit for bit;
- the walls' file has one surface per wall of summary.json.
The picture: the particles as spheres at their true size (Glyph: sphere, scale array
`radius`), coloured by state, and the walls semi-transparent. Exits non-zero on a failed check.
"""

import csv
import json
import os
import sys

from paraview import servermanager
from paraview.simple import (
    ColorBy,
    CSVReader,
    GetColorTransferFunction,
    GetScalarBar,
    Glyph,
    GetAnimationScene,
    PVDReader,
    Render,
    SaveScreenshot,
    Show,
    XMLPolyDataReader,
    CreateView,
)
from vtkmodules.util.numpy_support import vtk_to_numpy


def fail(message):
    print("paraview check FAILED: " + message, file=sys.stderr)
    sys.exit(1)


def csv_frames(path):
    """trajectories.csv as {time as float: {id: row}}, in file order."""
    frames = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            frames.setdefault(float(row["t"]), {})[int(row["id"])] = row
    return frames


def fetched(source, time):
    source.UpdatePipeline(time)
    data = servermanager.Fetch(source)
    return data


def check_frame(reader, time, rows):
    data = fetched(reader, time)
    n = data.GetNumberOfPoints()
    if n != len(rows):
        fail("t = %r: ParaView reads %d points, the CSV has %d rows" % (time, n, len(rows)))
    names = [data.GetPointData().GetArrayName(i) for i in range(data.GetPointData().GetNumberOfArrays())]
    expected = ["id", "kind", "diameter", "radius", "velocity", "speed", "state"]
    # A scene with rotation (friction) also writes each particle's spin, in both files.
    spin = n > 0 and "wx" in next(iter(rows.values()))
    if spin:
        expected.append("angular_velocity")
    if names != expected:
        fail("point arrays %r, expected %r" % (names, expected))
    if n == 0:
        return None
    ids = vtk_to_numpy(data.GetPointData().GetArray("id"))
    velocity = vtk_to_numpy(data.GetPointData().GetArray("velocity"))
    omega = vtk_to_numpy(data.GetPointData().GetArray("angular_velocity")) if spin else None
    for i in range(n):
        row = rows[int(ids[i])]
        x = data.GetPoint(i)
        want = (float(row["x"]), float(row["y"]), float(row["z"]))
        v = tuple(float(c) for c in velocity[i])
        want_v = (float(row["vx"]), float(row["vy"]), float(row["vz"]))
        if tuple(x) != want or v != want_v:
            fail("t = %r, id %d: ParaView reads x = %r, v = %r; the CSV has %r, %r" % (time, ids[i], x, v, want, want_v))
        if spin:
            w = tuple(float(c) for c in omega[i])
            want_w = (float(row["wx"]), float(row["wy"]), float(row["wz"]))
            if w != want_w:
                fail("t = %r, id %d: ParaView reads ω = %r; the CSV has %r" % (time, ids[i], w, want_w))
    first = int(ids[0])
    return first, data.GetPoint(0)


def main():
    if len(sys.argv) < 4:
        fail("usage: pvbatch render.py OUT_DIR SCENE_STEM PNG [TIME]")
    out, stem, png = sys.argv[1], sys.argv[2], sys.argv[3]
    frames = csv_frames(os.path.join(out, "trajectories.csv"))
    times = list(frames)

    reader = PVDReader(FileName=os.path.join(out, stem + ".pvd"))
    steps = list(reader.TimestepValues)
    if steps != times:
        fail("ParaView's time steps (%d) are not the CSV's frame times (%d)" % (len(steps), len(times)))
    time = float(sys.argv[4]) if len(sys.argv) > 4 else times[-1]
    if time not in frames:
        fail("t = %r is not a frame time" % time)
    check_frame(reader, times[0], frames[times[0]])
    first, x = check_frame(reader, time, frames[time])
    print("ParaView: %d time steps, t = %r: %d points, particle %d at (%r, %r, %r) as in the CSV"
          % (len(steps), time, len(frames[time]), first, x[0], x[1], x[2]))

    walls = XMLPolyDataReader(FileName=[os.path.join(out, stem + "_walls.vtp")])
    wall_data = fetched(walls, 0.0)
    with open(os.path.join(out, "summary.json")) as f:
        wall_count = len(json.load(f)["walls"])
    wall_index = vtk_to_numpy(wall_data.GetCellData().GetArray("wall"))
    if sorted(set(int(w) for w in wall_index)) != list(range(wall_count)):
        fail("the walls' file has surfaces for walls %r, the scene has %d" % (sorted(set(wall_index)), wall_count))
    print("ParaView: %d walls, %d triangles" % (wall_count, wall_data.GetNumberOfCells()))

    # The events: ParaView's CSV reader gives a table of every row, with the numeric columns.
    events = CSVReader(FileName=[os.path.join(out, "events.csv")])
    table = fetched(events, 0.0)
    with open(os.path.join(out, "events.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    columns = [table.GetColumnName(i) for i in range(table.GetNumberOfColumns())]
    if table.GetNumberOfRows() != len(rows) or not {"t", "st", "eps", "normal_speed"} <= set(columns):
        fail("events.csv: ParaView reads %d rows, columns %r; the file has %d rows" % (table.GetNumberOfRows(), columns, len(rows)))
    if rows and table.GetColumnByName("st").GetDataTypeAsString() not in ("double", "float"):
        fail("events.csv: st is not read as numbers")
    print("ParaView: events.csv is a table of %d rows (%s)" % (len(rows), ", ".join(columns)))

    # The picture.
    view = CreateView("RenderView")
    view.Background = [1.0, 1.0, 1.0]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    view.OrientationAxesVisibility = 0
    view.ViewTime = time
    GetAnimationScene().AnimationTime = time

    spheres = Glyph(Input=reader, GlyphType="Sphere")
    spheres.GlyphMode = "All Points"
    spheres.OrientationArray = ["POINTS", "No orientation array"]
    spheres.ScaleArray = ["POINTS", "radius"]
    spheres.ScaleFactor = 2.0  # ParaView's sphere glyph has radius 0.5: ×2 gives the true radius
    spheres.GlyphType.ThetaResolution = 16
    spheres.GlyphType.PhiResolution = 12
    shown = Show(spheres, view)
    ColorBy(shown, ("POINTS", "state"))
    lut = GetColorTransferFunction("state")
    # free blue, held orange, resting red: the MCAP's and the README's colours
    lut.InterpretValuesAsCategories = 1
    lut.Annotations = ["0", "free", "1", "held", "2", "resting"]
    lut.IndexedColors = [0.20, 0.50, 1.00, 1.00, 0.60, 0.10, 0.85, 0.15, 0.15]
    shown.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title = "state"
    bar.ComponentTitle = ""
    bar.TitleColor = [0.0, 0.0, 0.0]
    bar.LabelColor = [0.0, 0.0, 0.0]

    wall_display = Show(walls, view)
    wall_display.ColorArrayName = ["POINTS", ""]
    wall_display.DiffuseColor = [0.6, 0.6, 0.65]
    wall_display.AmbientColor = [0.6, 0.6, 0.65]
    wall_display.Opacity = 0.25

    # Gravity is along −z: z up, looking down on the particles from a corner, framing them (a
    # tall container would otherwise leave them small).
    glyphs = fetched(spheres, time)
    b = glyphs.GetBounds() if glyphs.GetNumberOfPoints() else wall_data.GetBounds()
    center = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-6)
    direction = [1.0, -1.6, 1.1]
    norm = sum(c * c for c in direction) ** 0.5
    view.CameraFocalPoint = center
    view.CameraPosition = [center[i] + 2.2 * size * direction[i] / norm for i in range(3)]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30.0
    Render(view)
    SaveScreenshot(png, view, ImageResolution=[1200, 900])
    if not os.path.isfile(png) or os.path.getsize(png) < 10000:
        fail("no picture at " + png)
    print("ParaView: rendered %s (%d glyph points for %d particles)" % (png, glyphs.GetNumberOfPoints(), len(frames[time])))


main()
