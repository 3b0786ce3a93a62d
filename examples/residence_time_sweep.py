"""Mean residence time of the toluene drops in the disc-and-doughnut contactor
(scenes/contactor_poiseuille.toml, the Poiseuille version) against the water's counter-current flow rate, through the Python
module.

    pip install "./python[sweep]" matplotlib
    python examples/residence_time_sweep.py            # writes out/contactor_flow_sweep.png

Each point is the shipped scene with one key changed, ``fluid.flow.mean_velocity`` (the mean
of the Poiseuille profile, downwards), run with fewer drops than the shipped scene so that the
sweep takes minutes: ``--rate`` drops/s injected for ``--injection`` s (default 250/s for 2 s,
500 drops; the scene: 1500 over 6 s). Nine points took 311 s on the project's 2-core machine
(release build, ``time python examples/residence_time_sweep.py``). The drops' residence times come from the top outlet (``Simulation.residence_times()``);
the band is their 10th–90th percentiles. The points run as tasks of ``wetbounce.sweep`` on a
Dask LocalCluster (one worker per core), or on the scheduler ``--scheduler`` names.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

import wetbounce as wb  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", type=Path, default=ROOT / "scenes/contactor_poiseuille.toml")
    ap.add_argument("--velocities", type=float, nargs="+", default=[0.0, 2.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0],
                    help="mean downward water velocities, mm/s")
    ap.add_argument("--rate", type=float, default=250.0, help="drops injected per second")
    ap.add_argument("--injection", type=float, default=2.0, help="seconds of injection")
    ap.add_argument("--duration", type=float, default=14.0, help="simulated seconds per run")
    ap.add_argument("--folder", type=Path, default=Path("out/contactor_flow_sweep"), help="the sweep's folder")
    ap.add_argument("--scheduler", help="a Dask scheduler's address (default: a LocalCluster here)")
    ap.add_argument("--out", type=Path, default=Path("out/contactor_flow_sweep.png"),
                    help="the picture (docs/figures/contactor_flow_sweep.png redraws docs/python.md's)")
    args = ap.parse_args()

    base = wb.Scene.load(args.scene).with_values({
        "injectors[0].rate": args.rate,
        "injectors[0].stop": args.injection,
        "simulation.duration": args.duration,
    })
    # A Poiseuille profile needs a non-zero mean velocity: "still water" is a tiny one.
    velocities = [-max(v, 1e-6) * 1e-3 for v in args.velocities]
    client = None
    if args.scheduler:
        from distributed import Client

        client = Client(args.scheduler)
    start = time.perf_counter()
    # Each point a task on Dask (a LocalCluster, one worker per core, unless --scheduler),
    # checkpointed into --folder: run again, the finished points are skipped.
    raw = wb.sweep(base, {"fluid.flow.mean_velocity": velocities}, client=client, out=args.folder)
    print(f"{len(raw)} runs of {args.duration} s simulated in {time.perf_counter() - start:.0f} s")
    radius = base["fluid.flow.radius"]
    baffles = [c for c in raw.columns if c.startswith(("wall_disc", "wall_doughnut"))]
    table = pd.DataFrame({
        "mean_velocity_mm_s": -raw["fluid.flow.mean_velocity"] * 1e3,
        "flow_l_h": -raw["fluid.flow.mean_velocity"] * math.pi * radius**2 * 1e3 * 3600,
        "injected": raw["particles_injected"],
        "left": raw["outlet_top_residence_count"],
        "mean_s": raw["outlet_top_residence_mean"],
        "p10_s": raw["outlet_top_residence_p10"],
        "p90_s": raw["outlet_top_residence_p90"],
        "baffle_impacts_per_drop": raw[baffles].sum(axis=1) / raw["particles_injected"].clip(lower=1),
        "wall_time_s": raw["wall_time_s"],
    })
    with pd.option_context("display.width", 160, "display.precision", 3):
        print(table.to_string(index=False))

    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=150)
    q = table["flow_l_h"]
    ax.fill_between(q, table["p10_s"], table["p90_s"], alpha=0.25, label="10th–90th percentile")
    ax.plot(q, table["mean_s"], "o-", label="mean")
    ax.set_xlabel("water flow rate, counter-current (L/h)")
    ax.set_ylabel("drop residence time (s)")
    per_mm_s = math.pi * base["fluid.flow.radius"] ** 2 * 3600  # L/h for 1 mm/s
    top = ax.secondary_xaxis("top", functions=(lambda x: x / per_mm_s, lambda v: v * per_mm_s))
    top.set_xlabel("mean water velocity (mm/s, downwards)")
    n = int(table["injected"].iloc[0])
    ax.set_title(f"Disc-and-doughnut contactor: {n} toluene drops (mean d 2.5 mm) per run", fontsize=10)
    ax.legend(loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
