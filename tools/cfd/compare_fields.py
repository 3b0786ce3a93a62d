#!/usr/bin/env python3
"""Compares (r, z) tables of wedge_to_axisymmetric.py made on different meshes (same grid).

Prints, for each table: the strongest downflow (the jets) and upflow (the discs' wakes), u_z on
the axis at a few heights, and the difference from the first table (the reference) over the
whole grid (rms and 99th percentile of |u - u_ref|, in m/s and in % of the 8 mm/s mean).

Needs numpy. Usage: python3 compare_fields.py REF.vti OTHER.vti [...]
"""
import sys

import numpy as np

from plot_field import read_vti


def main():
    tables = [(path, *read_vti(path)) for path in sys.argv[1:]]
    _, r0, z0, ur0, uz0 = tables[0]
    heights = (0.05, 0.11, 0.125, 0.17, 0.245, 0.30, 0.38)
    print("table: min u_z, max u_z (m/s); u_z on the axis at z = %s m; |u - u_ref| rms, 99th pct"
          % ", ".join("%g" % h for h in heights))
    for path, r, z, ur, uz in tables:
        if r.shape != r0.shape or z.shape != z0.shape:
            raise SystemExit("%s: not the reference's grid" % path)
        axis = [uz[int(round((h - z[0]) / (z[1] - z[0]))), 0] for h in heights]
        d = np.hypot(ur - ur0, uz - uz0)
        print("%s: %.5f %.5f; axis %s; diff rms %.3g m/s (%.1f %%), 99th %.3g m/s (%.1f %%)" % (
            path, uz.min(), uz.max(), " ".join("%.5f" % a for a in axis), np.sqrt((d ** 2).mean()),
            100 * np.sqrt((d ** 2).mean()) / 0.008, np.percentile(d, 99),
            100 * np.percentile(d, 99) / 0.008))


if __name__ == "__main__":
    main()
