#!/usr/bin/env python3
"""Writes the small VTK fixtures of tests/input/field_formats.rs (committed; CI does not run this).

A unit cube in 2 x 2 x 2 hexahedra (27 points, 8 cells) carrying the linear velocity
u = (1 + 2x - y, 3z, -x + 0.5y) as point data "U" and, at the cell centres, as cell data "U",
in the encodings a CFD user meets: XML unstructured grid in ASCII, inline base64 with UInt64
headers (foamToVTK's default), appended raw data, appended zlib-compressed data, and legacy
binary (big-endian) with cell data as a FIELD, as `foamToVTK -legacy` writes it.

    python3 tests/fields/make_fixtures.py      # writes tests/fields/hex_*.vt?
"""
import base64
import os
import struct
import zlib

here = os.path.dirname(os.path.abspath(__file__))
n = 2
pts = [(i / n, j / n, k / n) for k in range(n + 1) for j in range(n + 1) for i in range(n + 1)]


def pid(i, j, k):
    return i + (n + 1) * (j + (n + 1) * k)


cells = []
for k in range(n):
    for j in range(n):
        for i in range(n):
            cells.append([pid(i, j, k), pid(i + 1, j, k), pid(i + 1, j + 1, k), pid(i, j + 1, k),
                          pid(i, j, k + 1), pid(i + 1, j, k + 1), pid(i + 1, j + 1, k + 1), pid(i, j + 1, k + 1)])


def u(p):
    x, y, z = p
    return (1 + 2 * x - y, 3 * z, -x + 0.5 * y)


def centre(c):
    return tuple(sum(pts[v][a] for v in c) / 8 for a in range(3))


point_u = [c for p in pts for c in u(p)]
cell_u = [c for cell in cells for c in u(centre(cell))]
coords = [c for p in pts for c in p]
conn = [v for c in cells for v in c]
offsets = [8 * (i + 1) for i in range(len(cells))]
types = [12] * len(cells)

arrays = [  # (section, name, vtk type, struct code, components, values)
    ("Points", "Points", "Float64", "d", 3, coords),
    ("Cells", "connectivity", "Int64", "q", 1, conn),
    ("Cells", "offsets", "Int64", "q", 1, offsets),
    ("Cells", "types", "UInt8", "B", 1, types),
    ("PointData", "U", "Float32", "f", 3, point_u),
    ("CellData", "U", "Float32", "f", 3, cell_u),
]


def write(name, mode, header="UInt32"):
    hfmt = "<I" if header == "UInt32" else "<Q"
    appended = b""
    body = {"Points": [], "Cells": [], "PointData": [], "CellData": []}
    for section, aname, vtype, code, comps, values in arrays:
        raw = struct.pack("<%d%s" % (len(values), code), *values)
        attrs = 'type="%s" Name="%s" NumberOfComponents="%d"' % (vtype, aname, comps)
        if mode == "ascii":
            text = " ".join(repr(v) for v in values)
            body[section].append('<DataArray %s format="ascii">%s</DataArray>' % (attrs, text))
        elif mode == "base64":
            blob = base64.b64encode(struct.pack(hfmt, len(raw)) + raw).decode()
            body[section].append('<DataArray %s format="binary">%s</DataArray>' % (attrs, blob))
        else:
            if mode == "zlib":
                comp = zlib.compress(raw)
                block = struct.pack("<4" + hfmt[1], 1, len(raw), len(raw), len(comp)) + comp
            else:
                block = struct.pack(hfmt, len(raw)) + raw
            body[section].append('<DataArray %s format="appended" offset="%d"/>' % (attrs, len(appended)))
            appended += block
    comp = ' compressor="vtkZLibDataCompressor"' if mode == "zlib" else ""
    out = ['<?xml version="1.0"?>',
           '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="%s"%s>'
           % (header, comp),
           '<UnstructuredGrid>',
           '<Piece NumberOfPoints="%d" NumberOfCells="%d">' % (len(pts), len(cells))]
    for section in ["PointData", "CellData", "Points", "Cells"]:
        out.append("<%s>" % section)
        out.extend(body[section])
        out.append("</%s>" % section)
    out += ["</Piece>", "</UnstructuredGrid>"]
    data = "\n".join(out).encode()
    if appended:
        data += b'\n<AppendedData encoding="raw">\n_' + appended + b"\n</AppendedData>"
    data += b"\n</VTKFile>\n"
    with open(os.path.join(here, name), "wb") as f:
        f.write(data)


def write_legacy(name):
    be = lambda code, vals: struct.pack(">%d%s" % (len(vals), code), *vals)
    out = b"# vtk DataFile Version 2.0\nfixture in foamToVTK -legacy's layout\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
    out += b"POINTS %d float\n" % len(pts) + be("f", coords) + b"\n"
    cell_list = [v for c in cells for v in [8] + c]
    out += b"CELLS %d %d\n" % (len(cells), len(cell_list)) + be("i", cell_list) + b"\n"
    out += b"CELL_TYPES %d\n" % len(cells) + be("i", types) + b"\n"
    out += b"CELL_DATA %d\nFIELD attributes 1\n" % len(cells)
    out += b"U 3 %d float\n" % len(cells) + be("f", cell_u) + b"\n"
    out += b"POINT_DATA %d\nFIELD attributes 1\n" % len(pts)
    out += b"U 3 %d float\n" % len(pts) + be("f", point_u) + b"\n"
    with open(os.path.join(here, name), "wb") as f:
        f.write(out)


write("hex_ascii.vtu", "ascii")
write("hex_base64_uint64.vtu", "base64", "UInt64")
write("hex_appended_raw.vtu", "raw")
write("hex_appended_zlib.vtu", "zlib")
write_legacy("hex_legacy_binary.vtk")
