"""Mean residence time of toluene drops in the disc-and-doughnut contactor
(scenes/contactor_poiseuille.toml) against drop diameter and the water's counter-current flow
rate: a two-key sweep on a Dask cluster, drawn as a heat map.

    pip install "./python[sweep]" matplotlib
    python examples/contactor_heat_map.py               # out/contactor_heat_map.png

Each cell is the shipped scene with two keys changed — the injected drops' diameter
(``injectors[0].diameter``, one size per run) and the Poiseuille profile's mean velocity
(``fluid.flow.mean_velocity``, downwards) — with fewer drops than the shipped scene so that the
sweep takes minutes: ``--rate`` drops/s for ``--injection`` s. ``wetbounce.sweep`` runs the
cells as tasks on a LocalCluster on this machine (one per core), each checkpointing into
``--folder``; run it again and the finished cells are skipped. ``--scheduler ADDRESS`` sends
them to a running Dask scheduler instead (whose workers must see ``--folder``).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import wetbounce as wb  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", type=Path, default=ROOT / "scenes/contactor_poiseuille.toml")
    ap.add_argument("--diameters", type=float, nargs="+", default=[1.8, 2.2, 2.6, 3.0], help="drop diameters, mm")
    ap.add_argument("--velocities", type=float, nargs="+", default=[0.0, 4.0, 8.0, 12.0],
                    help="mean downward water velocities, mm/s")
    ap.add_argument("--rate", type=float, default=200.0, help="drops injected per second")
    ap.add_argument("--injection", type=float, default=1.0, help="seconds of injection")
    ap.add_argument("--duration", type=float, default=12.0, help="simulated seconds per run")
    ap.add_argument("--folder", type=Path, default=Path("out/contactor_heat_map"), help="the sweep's folder")
    ap.add_argument("--scheduler", help="a Dask scheduler's address (default: a LocalCluster here)")
    ap.add_argument("--out", type=Path, default=Path("out/contactor_heat_map.png"),
                    help="the picture (docs/figures/contactor_heat_map.png redraws the README's)")
    args = ap.parse_args()

    base = wb.Scene.load(args.scene).with_values({
        "injectors[0].rate": args.rate,
        "injectors[0].stop": args.injection,
        "simulation.duration": args.duration,
    })
    sizes = [{"distribution": "fixed", "value": d * 1e-3} for d in args.diameters]
    # A Poiseuille profile needs a non-zero mean velocity: "still water" is a tiny one.
    velocities = [-max(v, 1e-6) * 1e-3 for v in args.velocities]
    client = None
    if args.scheduler:
        from distributed import Client

        client = Client(args.scheduler)
    start = time.perf_counter()
    table = wb.sweep(
        base,
        {"injectors[0].diameter": sizes, "fluid.flow.mean_velocity": velocities},
        client=client,
        out=args.folder,
    )
    print(f"{len(table)} runs in {time.perf_counter() - start:.0f} s")
    table["d_mm"] = [s["value"] * 1e3 for s in table["injectors[0].diameter"]]
    radius = base["fluid.flow.radius"]
    table["flow_l_h"] = -table["fluid.flow.mean_velocity"] * math.pi * radius**2 * 1e3 * 3600
    grid = table.pivot(index="d_mm", columns="flow_l_h", values="outlet_top_residence_mean")
    print(grid.round(2).to_string())

    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=150)
    image = ax.imshow(grid.to_numpy(), origin="lower", aspect="auto", cmap="viridis")
    ax.set_xticks(range(len(grid.columns)), [f"{q:.0f}" for q in grid.columns])
    ax.set_yticks(range(len(grid.index)), [f"{d:.1f}" for d in grid.index])
    for (i, j), v in np.ndenumerate(grid.to_numpy()):
        ax.text(j, i, f"{v:.1f}", ha="center", va="center", color="white" if v < np.nanmean(grid) else "black", fontsize=8)
    ax.set_xlabel("water flow rate, counter-current (L/h)")
    ax.set_ylabel("drop diameter (mm)")
    fig.colorbar(image, ax=ax, label="mean residence time (s)")
    n = int(table["particles_injected"].iloc[0])
    ax.set_title(f"Disc-and-doughnut contactor: {n} toluene drops per run", fontsize=10)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
