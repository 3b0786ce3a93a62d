"""Sweeps on Dask ``distributed`` (issue 27): a LocalCluster on 127.0.0.1 with two worker
processes, the table against runs made one by one, and a worker killed in the middle of its task
— Dask runs the task again, which resumes from the variant's checkpoint, and the table is the
undisturbed one."""

from __future__ import annotations

import json
import os
import signal
import threading
import time
from pathlib import Path

import pytest

import wetbounce as wb

distributed = pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"

# The table's columns that differ between two runs of the same variants by nature.
VARYING = ["wall_time_s", "folder"]


def cluster(workers: int):
    c = distributed.LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        env={"RAYON_NUM_THREADS": "1"},
    )
    return c, distributed.Client(c)


def test_a_sweep_is_the_runs_one_by_one_whatever_the_workers(tmp_path):
    scene = wb.Scene.load(SCENES / "toluene_drop.toml")
    values = {"kinds[0].restitution_max": [0.5, 0.9], "kinds[0].surface_tension": [0.02, 0.035]}
    c, client = cluster(2)
    try:
        table = wb.sweep(scene, values, client=client, out=tmp_path / "two", progress=False)
    finally:
        client.close()
        c.close()
    assert list(table["kinds[0].restitution_max"]) == [0.5, 0.5, 0.9, 0.9]
    assert list(table["kinds[0].surface_tension"]) == [0.02, 0.035, 0.02, 0.035]
    assert (table["impacts_total"] > 0).all()
    one = wb.sweep(scene, values, out=tmp_path / "one", threads=os.cpu_count() or 1, progress=False)
    assert table.drop(columns=VARYING).equals(one.drop(columns=VARYING))
    # Each row is the run of its variant made here, one by one.
    for i, row in table.iterrows():
        sim = scene.with_values({k: row[k] for k in values}).simulation()
        sim.advance_to(scene.duration)
        assert sim.summary()["impacts"]["total"] == row["impacts_total"]
    # Started again, the sweep skips the finished variants.
    again = wb.sweep(scene, values, client=None, out=tmp_path / "two", threads=os.cpu_count() or 1, progress=False)
    assert again.equals(table)


def test_a_worker_killed_mid_task_gives_the_undisturbed_table(tmp_path):
    # Two variants of the 200-bead pour, ~1-2 s each, a checkpoint every 0.02 s.
    scene = wb.Scene.load(ROOT / "tests/scenes/pour_200.toml").with_values({"simulation.duration": 0.3})
    values = {"kinds[0].restitution_max": [0.6, 0.9]}
    undisturbed = wb.sweep(scene, values, out=tmp_path / "calm", checkpoint_every=0.02, progress=False)
    c, client = cluster(2)
    result = {}
    try:
        runner = threading.Thread(
            target=lambda: result.update(
                table=wb.sweep(scene, values, client=client, out=tmp_path / "storm", checkpoint_every=0.02, progress=False)
            )
        )
        runner.start()
        # Once a variant has checkpoints, kill a worker process outright.
        first = tmp_path / "storm" / "variant-0000" / "checkpoints"
        deadline = time.time() + 120
        while not (first.is_dir() and len(list(first.glob("*.wbck"))) >= 2):
            assert time.time() < deadline, "no checkpoint within 2 minutes"
            assert runner.is_alive(), "the sweep ended before a worker could be killed"
            time.sleep(0.01)
        pids = client.run(os.getpid)
        victim = next(iter(pids.values()))
        os.kill(victim, signal.SIGKILL)
        runner.join(timeout=300)
        assert not runner.is_alive()
    finally:
        client.close()
        c.close()
    storm = result["table"]
    records = [json.loads((tmp_path / "storm" / v / "variant.json").read_text()) for v in ("variant-0000", "variant-0001")]
    assert any(r["resumed_from"] for r in records), "no variant was resumed: the kill came too late"
    assert storm.drop(columns=VARYING).equals(undisturbed.drop(columns=VARYING))
    for name in ("trajectories.csv", "events.csv"):
        for v in ("variant-0000", "variant-0001"):
            assert (tmp_path / "calm" / v / name).read_bytes() == (tmp_path / "storm" / v / name).read_bytes()
