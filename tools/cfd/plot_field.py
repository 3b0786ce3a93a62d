#!/usr/bin/env python3
"""Draws tools/cfd/output/contactor_rz.vti (the (r, z) table of wedge_to_axisymmetric.py) as
tools/cfd/contactor_flow.png: u_z in colour with streamlines, on a diametral plane of the column
(the table mirrored about the axis), the whole column and a close-up of the lower baffles.

Needs numpy and matplotlib (e.g. python3 -m venv /tmp/v && /tmp/v/bin/pip install matplotlib).
Usage: python3 plot_field.py [IN.vti] [OUT.png]
"""
import base64
import os
import re
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
R = 0.025
# name, z of the outer rim, inner radius, outer radius, cone height (scenes/contactor.toml)
BAFFLES = [(0.08, 0.012, 0.025, 0.006), (0.14, 0.0, 0.017, -0.006), (0.20, 0.012, 0.025, 0.006),
           (0.26, 0.0, 0.017, -0.006), (0.32, 0.012, 0.025, 0.006)]


def read_vti(path):
    text = open(path).read()
    ext = list(map(int, re.search(r'WholeExtent="([^"]*)"', text).group(1).split()))
    origin = list(map(float, re.search(r'Origin="([^"]*)"', text).group(1).split()))
    spacing = list(map(float, re.search(r'Spacing="([^"]*)"', text).group(1).split()))
    m = re.search(r'<DataArray[^>]*format="(\w+)"[^>]*>(.*?)</DataArray>', text, re.S)
    if m.group(1) == "ascii":
        vals = np.array(m.group(2).split(), dtype=float)
    else:
        raw = base64.b64decode(m.group(2).strip())
        n = struct.unpack("<I", raw[:4])[0]
        vals = np.frombuffer(raw[4:4 + n], dtype="<f4").astype(float)
    nr, nz = ext[1] + 1, ext[5] + 1
    uv = vals.reshape(nz, nr, 2)
    r = origin[0] + spacing[0] * np.arange(nr)
    z = origin[2] + spacing[2] * np.arange(nz)
    return r, z, uv[:, :, 0], uv[:, :, 1]


def draw(ax, x, z, ux, uz, zlim, norm, density):
    sel = (z >= zlim[0]) & (z <= zlim[1])
    im = ax.pcolormesh(x, z[sel], uz[sel], cmap="RdBu_r", norm=norm, shading="auto")
    ax.streamplot(x, z[sel], ux[sel], uz[sel], color="k", linewidth=0.5, density=density,
                  arrowsize=0.6)
    for zc, inner, outer, h in BAFFLES:
        for s in (1, -1):
            rr = np.array([inner, outer]) * s
            ax.plot(rr * 1e0, [zc + h, zc], color="0.3", lw=2.5, solid_capstyle="butt")
    ax.axvline(R, color="0.3", lw=2)
    ax.axvline(-R, color="0.3", lw=2)
    ax.set_xlim(-R, R)
    ax.set_ylim(*zlim)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    return im


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "output", "contactor_rz.vti")
    dst = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "contactor_flow.png")
    r, z, ur, uz = read_vti(src)
    # Mirror the half-plane r >= 0 onto x < 0: u_x(-r) = -u_r(r).
    x = np.concatenate([-r[:0:-1], r])
    ux = np.concatenate([-ur[:, :0:-1], ur], axis=1)
    uzz = np.concatenate([uz[:, :0:-1], uz], axis=1)
    # streamplot wants a uniform grid; the table is one.
    lim = np.abs(uzz).max()
    norm = matplotlib.colors.TwoSlopeNorm(vmin=-lim, vcenter=0.0, vmax=0.5 * lim)
    fig = plt.figure(figsize=(11, 13))
    gs = fig.add_gridspec(1, 3, width_ratios=[1, 2.6, 0.12], wspace=0.25)
    ax1 = fig.add_subplot(gs[0])
    draw(ax1, x, z, ux, uzz, (0.0, 0.42), norm, 0.9)
    ax1.set_ylabel("z (m)")
    ax1.set_title("whole column")
    ax2 = fig.add_subplot(gs[1])
    im = draw(ax2, x, z, ux, uzz, (0.045, 0.225), norm, 2.2)
    ax2.set_title("doughnut_1, disc_1, doughnut_2")
    cb = fig.add_subplot(gs[2])
    fig.colorbar(im, cax=cb, label="u_z (m/s)  (mean -0.008, down)")
    fig.suptitle("scenes/contactor.toml: water, 8 mm/s mean downflow, laminar steady (OpenFOAM "
                 "simpleFoam, axisymmetric)", fontsize=11)
    fig.savefig(dst, dpi=80, bbox_inches="tight")
    print("wrote", dst)


if __name__ == "__main__":
    main()
