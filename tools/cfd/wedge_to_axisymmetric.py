#!/usr/bin/env python3
"""Turns foamToVTK's legacy .vtk of the contactor's wedge into a regular-grid VTK ImageData (.vti).

Input: the internal mesh of an axisymmetric wedge case (axis along z, a thin sector about the
x-z plane), as written by `foamToVTK -legacy` (ASCII or binary; UNSTRUCTURED_GRID of
hexahedra and prisms, with the velocity U as point data, i.e. interpolated to the mesh's
vertices, zero on the no-slip walls).

Each vertex at (x, y, z) is projected to (r, z) = (hypot(x, y), z), where its velocity becomes
u_r = (Ux x + Uy y)/r and u_z = Uz (the two vertices of a wedge edge, at +-angle/2, land on the
same (r, z) and are averaged). Each cell is then a convex quadrilateral (a triangle on the
axis) in the (r, z) plane, cut into triangles, and the velocity is linearly interpolated in
them onto a regular grid. Grid points in no cell (inside a baffle, which the mesh leaves out)
get velocity 0; so do points outside r <= R.

Output, one of:
  * 2-D (default): a table on the (r, z) half-plane, ImageData with WholeExtent
    "0 nr-1 0 0 0 nz-1", Origin "0 0 z0", Spacing "dr 1 dz": the image's x is r (0..R), its z
    is z; one point-data array "U_rz" of 2 components (u_r, u_z) in m/s. A reader rebuilds
    the 3-D velocity at (x, y, z) from r = hypot(x, y): u = u_r (x/r, y/r, 0) + (0, 0, u_z).
  * 3-D (--3d): a box covering the column, (-R..R) x (-R..R) x (z0..z1), point-data array "U"
    of 3 components (Ux, Uy, Uz), the axisymmetric field turned about the axis (0 outside the
    column).
Data are Float32, written either as ASCII or (default) inline base64 ("binary" in VTK's XML
terms: a UInt32 byte count, then the little-endian floats, base64-encoded together).

Usage:
  python3 wedge_to_axisymmetric.py IN.vtk OUT.vti [--spacing M] [--3d] [--ascii] [--radius R]
It also prints the volumetric flow rate through a few heights, integrated from the table
(2 pi r u_z dr), as a check of the conversion.

Dependencies: none (Python 3 standard library).
"""
import argparse
import base64
import math
import struct
import sys

LEGACY_TYPES = {
    "float": ("f", 4), "double": ("d", 8), "int": ("i", 4), "unsigned_int": ("I", 4),
    "long": ("q", 8), "unsigned_long": ("Q", 8), "vtktypeint64": ("q", 8),
    "vtktypeuint64": ("Q", 8), "short": ("h", 2), "unsigned_short": ("H", 2),
    "char": ("b", 1), "unsigned_char": ("B", 1), "vtkidtype": ("i", 4),
}


class LegacyVtk:
    """A minimal reader of legacy VTK UNSTRUCTURED_GRID files (versions 2.0 to 5.1)."""

    def __init__(self, path):
        with open(path, "rb") as f:
            self.data = f.read()
        self.pos = 0
        self.points = None
        self.cells = []       # list of vertex-index lists
        self.cell_types = []
        self.point_data = {}  # name -> (ncomp, flat list)
        self.cell_data = {}
        self.field_data = {}
        self._parse()

    def _line(self):
        while True:
            end = self.data.find(b"\n", self.pos)
            if end < 0:
                if self.pos >= len(self.data):
                    return None
                end = len(self.data)
            text = self.data[self.pos:end].decode("ascii", "replace").strip()
            self.pos = end + 1
            if text:
                return text

    def _values(self, n, vtype):
        code, size = LEGACY_TYPES[vtype.lower()]
        if self.binary:
            nbytes = n * size
            out = struct.unpack(">%d%s" % (n, code), self.data[self.pos:self.pos + nbytes])
            self.pos += nbytes
            return list(out)
        out = []
        conv = float if code in "fd" else int
        while len(out) < n:
            out.extend(conv(t) for t in self._line().split())
        return out

    def _parse(self):
        self._line()              # "# vtk DataFile Version x.y"
        self.title = self._line()
        self.binary = self._line().upper() == "BINARY"
        target = None
        while True:
            line = self._line()
            if line is None:
                break
            words = line.split()
            key = words[0].upper()
            if key == "DATASET":
                if words[1].upper() != "UNSTRUCTURED_GRID":
                    raise SystemExit("only UNSTRUCTURED_GRID is read, not %s" % words[1])
            elif key == "POINTS":
                target = None
                self.points = self._values(3 * int(words[1]), words[2])
            elif key == "CELLS":
                n, size = int(words[1]), int(words[2])
                nxt = self._peek_word()
                if nxt == "OFFSETS":           # version 5.1: OFFSETS and CONNECTIVITY arrays
                    w = self._line().split()
                    offsets = self._values(n, w[1])
                    w = self._line().split()
                    conn = self._values(size, w[1])
                    self.cells = [conn[offsets[i]:offsets[i + 1]] for i in range(n - 1)]
                else:
                    flat = self._values(size, "int")
                    i = 0
                    for _ in range(n):
                        k = flat[i]
                        self.cells.append(flat[i + 1:i + 1 + k])
                        i += k + 1
            elif key == "CELL_TYPES":
                self.cell_types = self._values(int(words[1]), "int")
            elif key == "CELL_DATA":
                target, ntuples = self.cell_data, int(words[1])
            elif key == "POINT_DATA":
                target, ntuples = self.point_data, int(words[1])
            elif key == "FIELD":
                if target is None:          # dataset-level field data (e.g. TimeValue)
                    target = self.field_data
                for _ in range(int(words[2])):
                    w = self._line().split()
                    name, ncomp, nt, vtype = w[0], int(w[1]), int(w[2]), w[3]
                    target[name] = (ncomp, self._values(ncomp * nt, vtype))
            elif key in ("SCALARS", "VECTORS", "NORMALS"):
                name, vtype = words[1], words[2]
                ncomp = 3 if key != "SCALARS" else (int(words[3]) if len(words) > 3 else 1)
                if key == "SCALARS":
                    self._line()            # LOOKUP_TABLE
                target[name] = (ncomp, self._values(ncomp * ntuples, vtype))
            elif key == "METADATA":
                while self._line_raw().strip():
                    pass
            # other keywords (e.g. a time value) are skipped

    def _peek_word(self):
        save = self.pos
        line = self._line()
        self.pos = save
        return line.split()[0].upper() if line else None

    def _line_raw(self):
        end = self.data.find(b"\n", self.pos)
        end = len(self.data) if end < 0 else end
        text = self.data[self.pos:end].decode("ascii", "replace")
        self.pos = end + 1
        return text


def axisymmetric_triangles(vtk):
    """(r, z) triangles with (u_r, u_z) at their corners, from the wedge's cells."""
    if "U" not in vtk.point_data:
        raise SystemExit("no point-data U in the file (run foamToVTK without -no-point-data)")
    ncomp, u = vtk.point_data["U"]
    p = vtk.points
    npts = len(p) // 3
    key_of = [None] * npts
    sums = {}
    for i in range(npts):
        x, y, z = p[3 * i:3 * i + 3]
        r = math.hypot(x, y)
        ur = (u[3 * i] * x + u[3 * i + 1] * y) / r if r > 1e-12 else 0.0
        k = (round(r * 1e9), round(z * 1e9))   # merge the +-angle/2 copies (1 nm tolerance)
        key_of[i] = k
        s = sums.get(k)
        if s is None:
            sums[k] = [r, z, ur, u[3 * i + 2], 1]
        else:
            s[2] += ur
            s[3] += u[3 * i + 2]
            s[4] += 1
    nodes = {k: [s[0], s[1], s[2] / s[4], s[3] / s[4]] for k, s in sums.items()}
    polys = []
    edges = {}
    for cell in vtk.cells:
        keys = list(dict.fromkeys(key_of[i] for i in cell))
        if len(keys) < 3:
            continue
        cr = sum(nodes[k][0] for k in keys) / len(keys)
        cz = sum(nodes[k][1] for k in keys) / len(keys)
        keys.sort(key=lambda k: math.atan2(nodes[k][1] - cz, nodes[k][0] - cr))
        polys.append(keys)
        for a, b in zip(keys, keys[1:] + keys[:1]):
            e = (a, b) if a < b else (b, a)
            edges[e] = edges.get(e, 0) + 1
    # No slip: foamToVTK's point values on a wall are not the wall's zero (the wedge
    # constraint, not the wall, sets the points shared by both), so the velocity is set to 0
    # on every edge of the (r, z) mesh's boundary but the axis, the inlet and the outlet.
    zs = [n[1] for n in nodes.values()]
    zlo, zhi = min(zs), max(zs)
    walls = 0
    for (a, b), count in edges.items():
        if count != 1:
            continue
        na, nb = nodes[a], nodes[b]
        if max(na[0], nb[0]) < 1e-9 or min(na[1], nb[1]) > zhi - 1e-9 or max(na[1], nb[1]) < zlo + 1e-9:
            continue
        for n in (na, nb):
            n[2] = n[3] = 0.0
        walls += 1
    tris = []
    for keys in polys:
        pts = [tuple(nodes[k]) for k in keys]
        for j in range(1, len(pts) - 1):
            tris.append((pts[0], pts[j], pts[j + 1]))
    return tris, walls


def rasterize(tris, r0, dr, nr, z0, dz, nz):
    """Linear interpolation of (u_r, u_z) from the triangles onto the regular (r, z) grid."""
    ur = [0.0] * (nr * nz)
    uz = [0.0] * (nr * nz)
    hit = bytearray(nr * nz)
    eps = 1e-4  # the file's float32 coordinates are ~1e-8 m off (e.g. r = R - 5e-10)
    for a, b, c in tris:
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if abs(det) < 1e-20:
            continue
        rmin, rmax = min(a[0], b[0], c[0]), max(a[0], b[0], c[0])
        zmin, zmax = min(a[1], b[1], c[1]), max(a[1], b[1], c[1])
        i0 = max(0, math.ceil((rmin - r0) / dr - 1e-3))
        i1 = min(nr - 1, math.floor((rmax - r0) / dr + 1e-3))
        k0 = max(0, math.ceil((zmin - z0) / dz - 1e-3))
        k1 = min(nz - 1, math.floor((zmax - z0) / dz + 1e-3))
        for k in range(k0, k1 + 1):
            z = z0 + k * dz
            for i in range(i0, i1 + 1):
                n = k * nr + i
                if hit[n]:
                    continue
                r = r0 + i * dr
                l1 = ((b[0] - r) * (c[1] - z) - (c[0] - r) * (b[1] - z)) / det
                l2 = ((c[0] - r) * (a[1] - z) - (a[0] - r) * (c[1] - z)) / det
                l3 = 1.0 - l1 - l2
                if l1 < -eps or l2 < -eps or l3 < -eps:
                    continue
                ur[n] = l1 * a[2] + l2 * b[2] + l3 * c[2]
                uz[n] = l1 * a[3] + l2 * b[3] + l3 * c[3]
                hit[n] = 1
    return ur, uz, hit


def encode(values, ascii_out):
    if ascii_out:
        lines = []
        for j in range(0, len(values), 12):
            lines.append(" ".join("%.6g" % v for v in values[j:j + 12]))
        return "ascii", "\n".join(lines)
    raw = struct.pack("<%df" % len(values), *values)
    return "binary", base64.b64encode(struct.pack("<I", len(raw)) + raw).decode("ascii")


def write_vti(path, extent, origin, spacing, name, ncomp, values, ascii_out, comment):
    fmt, text = encode(values, ascii_out)
    ext = " ".join(map(str, extent))
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<!-- %s -->\n' % comment)
        f.write('<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" header_type="UInt32">\n')
        f.write('  <ImageData WholeExtent="%s" Origin="%s" Spacing="%s">\n' % (
            ext, " ".join("%.9g" % v for v in origin), " ".join("%.9g" % v for v in spacing)))
        f.write('    <Piece Extent="%s">\n      <PointData%s>\n'
                % (ext, ' Vectors="%s"' % name if ncomp == 3 else ""))
        f.write('        <DataArray type="Float32" Name="%s" NumberOfComponents="%d" format="%s">\n'
                % (name, ncomp, fmt))
        f.write(text)
        f.write('\n        </DataArray>\n      </PointData>\n      <CellData>\n      </CellData>\n')
        f.write('    </Piece>\n  </ImageData>\n</VTKFile>\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("input", help="foamToVTK -legacy output (internal mesh), .vtk")
    ap.add_argument("output", help="the .vti to write")
    ap.add_argument("--spacing", type=float, default=None,
                    help="grid spacing in m (default 0.25e-3 in 2-D, 1e-3 in 3-D)")
    ap.add_argument("--3d", dest="three_d", action="store_true", help="write the full 3-D box")
    ap.add_argument("--ascii", action="store_true", help="ASCII data instead of base64")
    ap.add_argument("--radius", type=float, default=0.025, help="column radius R (m)")
    ap.add_argument("--zmin", type=float, default=0.0,
                    help="lowest z kept (m; default 0, the scene's column: the mesh goes on below)")
    ap.add_argument("--zmax", type=float, default=0.42, help="highest z kept (m; default 0.42)")
    args = ap.parse_args()

    vtk = LegacyVtk(args.input)
    tris, walls = axisymmetric_triangles(vtk)
    zs = vtk.points[2::3]
    z0, z1 = max(min(zs), args.zmin), min(max(zs), args.zmax)
    # The file's coordinates are float32: snap the ends to the requested ones when that close.
    if abs(z0 - args.zmin) < 1e-6:
        z0 = args.zmin
    if abs(z1 - args.zmax) < 1e-6:
        z1 = args.zmax
    R = args.radius
    types = {}
    for t in vtk.cell_types:
        types[t] = types.get(t, 0) + 1
    print("read %s: %d points, %d cells (VTK cell types %s), point data %s, cell data %s; "
          "%d triangles in (r, z), %d wall edges set to 0; z %.4g .. %.4g m kept"
          % (args.input, len(vtk.points) // 3, len(vtk.cells), types, sorted(vtk.point_data),
             sorted(vtk.cell_data), len(tris), walls, z0, z1))

    h2 = args.spacing if (args.spacing and not args.three_d) else 0.25e-3
    nr = int(round(R / h2)) + 1
    nz = int(round((z1 - z0) / h2)) + 1
    dr, dz = R / (nr - 1), (z1 - z0) / (nz - 1)
    ur, uz, hit = rasterize(tris, 0.0, dr, nr, z0, dz, nz)
    print("(r, z) grid %d x %d, dr %.4g m, dz %.4g m: %d points in the fluid, %d in baffles or walls"
          % (nr, nz, dr, dz, sum(hit), nr * nz - sum(hit)))
    for zq in (0.01, 0.05, 0.11, 0.17, 0.23, 0.29, 0.36, 0.41):
        k = int(round((zq - z0) / dz))
        q = 0.0
        for i in range(nr - 1):
            fa = 2 * math.pi * (i * dr) * uz[k * nr + i]
            fb = 2 * math.pi * ((i + 1) * dr) * uz[k * nr + i + 1]
            q += 0.5 * (fa + fb) * dr
        print("  flow rate at z = %.4f m: %.6e m3/s" % (z0 + k * dz, q))

    if not args.three_d:
        vals = []
        for n in range(nr * nz):
            vals.append(ur[n])
            vals.append(uz[n])
        write_vti(args.output, (0, nr - 1, 0, 0, 0, nz - 1), (0.0, 0.0, z0), (dr, 1.0, dz),
                  "U_rz", 2, vals, args.ascii,
                  "Axisymmetric velocity (m/s) of tools/cfd/case: image x = r (m, 0..R), image z = z "
                  "(m); U_rz = (u_r, u_z); 0 inside baffles. 3-D: u = u_r (x/r, y/r, 0) + (0, 0, u_z).")
        print("wrote %s (2-D, %d x 1 x %d points)" % (args.output, nr, nz))
        return

    h = args.spacing or 1e-3
    n = int(round(2 * R / h)) + 1
    hx = 2 * R / (n - 1)
    nz3 = int(round((z1 - z0) / h)) + 1
    hz = (z1 - z0) / (nz3 - 1)

    def sample(r, z):
        # Bilinear in the (r, z) table.
        fr, fz = r / dr, (z - z0) / dz
        i, k = min(int(fr), nr - 2), min(int(fz), nz - 2)
        a, b = fr - i, fz - k
        out = []
        for arr in (ur, uz):
            out.append((1 - a) * (1 - b) * arr[k * nr + i] + a * (1 - b) * arr[k * nr + i + 1]
                       + (1 - a) * b * arr[(k + 1) * nr + i] + a * b * arr[(k + 1) * nr + i + 1])
        return out

    vals = []
    for k in range(nz3):
        z = z0 + k * hz
        for j in range(n):
            y = -R + j * hx
            for i in range(n):
                x = -R + i * hx
                r = math.hypot(x, y)
                if r > R:
                    vals.extend((0.0, 0.0, 0.0))
                    continue
                a, w = sample(r, z)
                if r > 1e-12:
                    vals.extend((a * x / r, a * y / r, w))
                else:
                    vals.extend((0.0, 0.0, w))
    write_vti(args.output, (0, n - 1, 0, n - 1, 0, nz3 - 1), (-R, -R, z0), (hx, hx, hz), "U", 3,
              vals, args.ascii, "Velocity (m/s) of tools/cfd/case, the axisymmetric field turned "
              "about the z axis; 0 outside the column and inside baffles.")
    print("wrote %s (3-D, %d x %d x %d points)" % (args.output, n, n, nz3))


if __name__ == "__main__":
    sys.exit(main())
