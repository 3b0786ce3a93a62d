#!/usr/bin/env python3
"""Writes case/system/blockMeshDict: an axisymmetric wedge of scenes/contactor.toml's column.

The column (radius 0.025 m, z from 0 to 0.42 m, axis along z) is cut in the (r, z) plane into
three radial columns of blocks, split at the baffles' rims (r = 0.012 and 0.017 m), and into
horizontal layers whose bounding lines follow the baffles' conical surfaces. Each baffle is a
layer 1 mm thick (measured along z) centred on the engine's zero-thickness surface; the blocks
of that layer that the baffle covers are left out, and their faces become the baffle's wall
patch. The wedge spans -ANGLE/2..+ANGLE/2 about the x-z plane, one cell thick; the blocks on
the axis have their two axis vertices collapsed (prisms).

Geometry as in src/walls/annulus.rs: the outer rim lies in the plane z = center; the inner rim
(a doughnut's, at r = inner_radius) or the centre (a disc's, at r = 0) is cone_height above it,
and the surface between them is a straight cone generator.

Usage: python3 make_blockmesh.py [cell_size_m [output_path]]
       (defaults 0.00035 and case/system/blockMeshDict beside this script)
Dependency-free; the generated dict is committed, so running the case needs no Python.
"""
import math
import os
import sys

R = 0.025          # shell radius (m)
Z_TOP = 0.42       # shell length (m); inlet at the top
Z_OUT = -0.10      # outlet: the column is continued 0.1 m below the scene's z = 0, whose
                   # plane the jet from doughnut_1 still crosses with backflow near the wall
N_OUT = 60         # cells along z in that extension, growing downwards from the size at z = 0
THICK = 0.001      # baffle thickness in the mesh (m), along z
ANGLE = 5.0        # wedge angle (degrees)

# name, kind, centre z, inner radius, outer radius, cone height  (scenes/contactor.toml)
BAFFLES = [
    ("doughnut_1", "doughnut", 0.08, 0.012, 0.025, 0.006),
    ("disc_1", "disc", 0.14, 0.0, 0.017, -0.006),
    ("doughnut_2", "doughnut", 0.20, 0.012, 0.025, 0.006),
    ("disc_2", "disc", 0.26, 0.0, 0.017, -0.006),
    ("doughnut_3", "doughnut", 0.32, 0.012, 0.025, 0.006),
]

STATIONS = [0.0, 0.012, 0.017, R]  # radial block boundaries


def surface_z(baffle, r):
    """The engine's baffle surface height at radius r, continued flat past its rims."""
    _, _, zc, inner, outer, h = baffle
    r = min(max(r, inner), outer)
    return zc + h * (outer - r) / (outer - inner)


def covered_columns(baffle):
    """Indices of the radial columns of blocks the baffle covers."""
    _, _, _, inner, outer, _ = baffle
    return [c for c in range(3) if STATIONS[c] >= inner - 1e-12 and STATIONS[c + 1] <= outer + 1e-12]


def main():
    h = float(sys.argv[1]) if len(sys.argv) > 1 else 0.00035
    nr = [max(1, round((STATIONS[c + 1] - STATIONS[c]) / h)) for c in range(3)]

    # Levels: lists of z at each station, bottom to top.
    levels = [[Z_OUT] * 4, [0.0] * 4]
    baffle_layer = {}  # layer index -> baffle
    for b in BAFFLES:
        mid = [surface_z(b, r) for r in STATIONS]
        baffle_layer[len(levels)] = b
        levels.append([z - THICK / 2 for z in mid])
        levels.append([z + THICK / 2 for z in mid])
    levels.append([Z_TOP] * 4)
    for lo, hi in zip(levels, levels[1:]):
        assert all(b > a for a, b in zip(lo, hi)), (lo, hi)
    nlayers = len(levels) - 1
    nz = []
    grading = []
    for j in range(nlayers):
        dz = max(levels[j + 1][i] - levels[j][i] for i in range(4))
        nz.append(max(2, math.ceil(dz / h - 1e-9)))
        grading.append(1.0)
    # The extension: N_OUT cells whose sizes grow geometrically downwards from h at z = 0.
    nz[0] = N_OUT
    lo, hi = 1.0, 2.0           # q = ratio of a cell to the one above it, by bisection
    for _ in range(200):
        q = 0.5 * (lo + hi)
        if h * sum(q ** k for k in range(N_OUT)) > -Z_OUT:
            hi = q
        else:
            lo = q
    grading[0] = q ** -(N_OUT - 1)  # blockMesh: last (top) cell / first (bottom) cell
    a = math.radians(ANGLE / 2)
    verts = []
    index = {}

    def vid(i, j, s):
        key = (i, j, 0 if i == 0 else s)
        if key not in index:
            r = STATIONS[i]
            index[key] = len(verts)
            verts.append((r * math.cos(a), (-1 if key[2] == 0 else 1) * r * math.sin(a), levels[j][i]))
        return index[key]

    for j in range(len(levels)):
        for i in range(4):
            for s in (0, 1):
                vid(i, j, s)

    blocks = []
    patches = {name: [] for name in ["inlet", "outlet", "shell", "axis", "front", "back"] + [b[0] for b in BAFFLES]}

    def exists(c, j):
        return 0 <= j < nlayers and not (j in baffle_layer and c in covered_columns(baffle_layer[j]))

    for j in range(nlayers):
        for c in range(3):
            if not exists(c, j):
                continue
            v = [vid(c, j, 0), vid(c + 1, j, 0), vid(c + 1, j, 1), vid(c, j, 1),
                 vid(c, j + 1, 0), vid(c + 1, j + 1, 0), vid(c + 1, j + 1, 1), vid(c, j + 1, 1)]
            blocks.append((v, (nr[c], 1, nz[j]), grading[j]))
            faces = {  # outward-ordered hex faces
                "xmin": (v[0], v[4], v[7], v[3]), "xmax": (v[1], v[2], v[6], v[5]),
                "ymin": (v[0], v[1], v[5], v[4]), "ymax": (v[3], v[7], v[6], v[2]),
                "zmin": (v[0], v[3], v[2], v[1]), "zmax": (v[4], v[5], v[6], v[7]),
            }
            patches["back"].append(faces["ymin"])
            patches["front"].append(faces["ymax"])
            if c == 0:
                patches["axis"].append(faces["xmin"])
            if c == 2:
                patches["shell"].append(faces["xmax"])
            if j == 0:
                patches["outlet"].append(faces["zmin"])
            if j == nlayers - 1:
                patches["inlet"].append(faces["zmax"])
            # Faces against a left-out (baffle) block.
            if j - 1 in baffle_layer and not exists(c, j - 1):
                patches[baffle_layer[j - 1][0]].append(faces["zmin"])
            if j + 1 in baffle_layer and not exists(c, j + 1):
                patches[baffle_layer[j + 1][0]].append(faces["zmax"])
            if j in baffle_layer:
                if c > 0 and not exists(c - 1, j):
                    patches[baffle_layer[j][0]].append(faces["xmin"])
                if c < 2 and not exists(c + 1, j):
                    patches[baffle_layer[j][0]].append(faces["xmax"])

    types = {"inlet": "patch", "outlet": "patch", "axis": "empty", "front": "wedge", "back": "wedge"}
    out = []
    out.append("/*  Generated by tools/cfd/make_blockmesh.py (cell size %g m): do not edit by hand. */\n" % h)
    out.append("FoamFile\n{\n    version     2.0;\n    format      ascii;\n    class       dictionary;\n"
               "    object      blockMeshDict;\n}\n\n")
    out.append("// Wedge %g deg about the x-z plane, axis along z; radial cells %s; axial cells per layer %s\n"
               % (ANGLE, nr, nz))
    out.append("// Cells: %d\n\nscale 1;\n\nvertices\n(\n" % sum(n[0] * n[2] for _, n, _ in blocks))
    for k, (x, y, z) in enumerate(verts):
        out.append("    (%.9g %.9g %.9g) // %d\n" % (x, y, z, k))
    out.append(");\n\nblocks\n(\n")
    for v, n, g in blocks:
        out.append("    hex (%s) (%d %d %d) simpleGrading (1 1 %.9g)\n" % (" ".join(map(str, v)), *n, g))
    out.append(");\n\nedges\n(\n);\n\nboundary\n(\n")
    for name, faces in patches.items():
        out.append("    %s\n    {\n        type %s;\n        faces\n        (\n" % (name, types.get(name, "wall")))
        for f in faces:
            out.append("            (%s)\n" % " ".join(map(str, f)))
        out.append("        );\n    }\n")
    out.append(");\n\nmergePatchPairs\n(\n);\n")
    path = sys.argv[2] if len(sys.argv) > 2 else \
        os.path.join(os.path.dirname(os.path.abspath(__file__)), "case", "system", "blockMeshDict")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("".join(out))
    print("wrote %s: %d blocks, %d cells, radial %s, axial %d" % (path, len(blocks),
          sum(n[0] * n[2] for _, n, _ in blocks), nr, sum(nz)))


if __name__ == "__main__":
    main()
