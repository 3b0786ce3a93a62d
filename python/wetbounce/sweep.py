"""Sweeps: a family of runs of one scene, each variant a task on a Dask ``distributed`` cluster.

    import wetbounce
    table = wetbounce.sweep(
        "scenes/column.toml",
        {"kinds[0].restitution_max": [0.5, 0.7, 0.9], "injectors[0].rate": [200.0, 500.0]},
        out="sweep/column",
    )

Every combination of the values is a variant (the product, in the order given); each runs as
``Scene.with_values(variant).simulation().run(...)`` into ``out/variant-NNNN/`` with
checkpoints, and the call returns a pandas DataFrame, one row per variant in that order: the
values, the summary's figures, the wall time and the output folder.

- **Cluster.** ``client=None`` starts a ``LocalCluster`` on 127.0.0.1 (as many worker processes
  as cores // ``threads``, each engine with ``threads`` threads, so the machine is not
  oversubscribed) and closes it at the end; any ``distributed.Client`` may be passed instead
  (a scheduler on other machines, dask-jobqueue, dask-ssh), whose workers see ``out`` (a
  shared file system).
- **Faults.** A variant checkpoints into its folder (``checkpoint_every`` simulated seconds,
  default a tenth of the run). When a worker dies, Dask runs the task again elsewhere, and the
  task resumes from the variant's last checkpoint: the result is the one an undisturbed run
  gives, bit for bit. A sweep started again skips the variants that finished (their
  ``variant.json``) and resumes the others.
- **Identity.** The table does not depend on the number of workers, on the order tasks ran in,
  or on a worker's death: every column but ``wall_time_s`` is the same.
"""

from __future__ import annotations

import itertools
import json
import math
import os
from pathlib import Path
from typing import Any, Mapping, Sequence

__all__ = ["sweep", "run_variant"]


def _variants(values: Mapping[str, Sequence[Any]]) -> list[dict[str, Any]]:
    if not values:
        return [{}]
    keys = list(values)
    for k, v in values.items():
        if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
            raise TypeError(f"sweep: the values of {k!r} must be a list, got {v!r}")
        if len(list(v)) == 0:
            raise ValueError(f"sweep: {k!r} has no values")
    return [dict(zip(keys, combo)) for combo in itertools.product(*(list(values[k]) for k in keys))]


def _flat(summary: dict[str, Any]) -> dict[str, Any]:
    """The summary's figures as one flat row."""
    row: dict[str, Any] = {}
    imp = summary.get("impacts", {})
    for k in ("total", "held", "bounced", "deposited", "mean_st", "mean_eps"):
        row[f"impacts_{k}"] = imp.get(k, math.nan)
    parts = summary.get("particles", {})
    for k in ("alive", "injected", "removed_by_outlets", "lost_non_finite"):
        row[f"particles_{k}"] = parts.get(k, 0)
    for o in summary.get("outlets", []):
        d = o.get("residence_time_s", {}) or {}
        for k in ("count", "mean", "p10", "p50", "p90"):
            v = d.get(k)
            row[f"outlet_{o['name']}_residence_{k}"] = math.nan if v is None else v
    for w in summary.get("walls", []):
        row[f"wall_{w['name']}_impacts"] = w.get("impacts", 0)
    row["time_s"] = summary.get("time_s", math.nan)
    row["steps"] = summary.get("steps", 0)
    return row


def run_variant(
    scene: Any,
    values: dict[str, Any],
    folder: str,
    checkpoint_every: float | None = None,
    formats: Sequence[str] = ("csv",),
) -> dict[str, Any]:
    """Runs one variant of ``scene`` (a :class:`wetbounce.Scene`) with ``values`` set, into
    ``folder``: skipped when it finished before (``variant.json``), resumed from its last
    checkpoint when it has one (``variant.json`` names it: ``resumed_from``), else run from the
    start. Returns its row. The task Dask runs."""
    from ._wetbounce import Simulation

    out = Path(folder)
    done = out / "variant.json"
    if done.is_file():
        record = json.loads(done.read_text())
        if record.get("values") == json.loads(json.dumps(values, default=float)):
            return record["row"]
    variant = scene.with_values(values) if values else scene
    every = checkpoint_every if checkpoint_every is not None else variant.duration / 10.0
    checkpoints = sorted((out / "checkpoints").glob("checkpoint-*.wbck"))
    sim, resumed_from = None, None
    for ck in reversed(checkpoints):
        try:
            sim, resumed_from = Simulation.load(ck), ck.name
            break
        except ValueError:
            continue  # a damaged one: the one before it
    if sim is None:
        sim = variant.simulation()
    sim.run(out, formats=list(formats), quiet=True, checkpoint_every=every)
    summary = json.loads((out / "summary.json").read_text())
    row = dict(values)
    row.update(_flat(summary))
    row["wall_time_s"] = summary.get("wall_time_s", math.nan)
    row["folder"] = str(out)
    tmp = done.with_suffix(".json.partial")
    record = {"values": values, "row": row, "resumed_from": resumed_from}
    tmp.write_text(json.dumps(record, default=float))
    os.replace(tmp, done)
    return row


def sweep(
    scene: Any,
    values: Mapping[str, Sequence[Any]],
    *,
    client: Any = None,
    out: str | os.PathLike[str] = "sweep",
    threads: int = 1,
    checkpoint_every: float | None = None,
    formats: Sequence[str] = ("csv",),
    progress: bool = True,
):
    """Runs every combination of ``values`` (``{"key.path": [v1, v2, …]}``, the keys of
    :meth:`Scene.with_values`) of ``scene`` (a :class:`Scene` or a scene file) as tasks on a Dask
    cluster, and returns a pandas DataFrame with one row per variant (module documentation).

    ``client``: a ``distributed.Client``; by default a ``LocalCluster`` on 127.0.0.1 with
    ``os.cpu_count() // threads`` workers, started and closed here. ``threads``: the engine's
    threads per variant (``RAYON_NUM_THREADS`` of the local workers). ``out``: the sweep's
    folder, one ``variant-NNNN`` folder per variant. ``checkpoint_every``: simulated seconds
    between a variant's checkpoints (default a tenth of its duration). ``formats``: what each
    variant writes (``"csv"`` by default; ``"mcap"``, ``"vtk"`` too). ``progress``: Dask's
    progress bar (in a terminal or a notebook).
    """
    import pandas as pd
    from distributed import Client, LocalCluster

    from ._wetbounce import Scene

    if not isinstance(scene, Scene):
        scene = Scene.load(scene)
    if threads < 1:
        raise ValueError(f"sweep: threads must be at least 1, got {threads}")
    variants = _variants(values)
    root = Path(out).resolve()
    root.mkdir(parents=True, exist_ok=True)
    # Every variant is checked before a task is sent: a bad value fails here, naming its key.
    for v in variants:
        if v:
            scene.with_values(v)
    cluster = None
    if client is None:
        workers = max(1, (os.cpu_count() or 1) // threads)
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            env={"RAYON_NUM_THREADS": str(threads)},
        )
        client = Client(cluster)
    try:
        futures = [
            client.submit(
                run_variant,
                scene,
                v,
                str(root / f"variant-{i:04d}"),
                checkpoint_every,
                tuple(formats),
                key=f"wetbounce-variant-{i:04d}-{abs(hash((str(root), json.dumps(v, default=str)))):x}",
                pure=False,
                retries=2,
            )
            for i, v in enumerate(variants)
        ]
        if progress:
            from distributed import progress as dask_progress

            dask_progress(futures)
        rows = client.gather(futures)
    finally:
        if cluster is not None:
            client.close()
            cluster.close()
    return pd.DataFrame(rows)
