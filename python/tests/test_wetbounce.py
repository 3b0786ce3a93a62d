"""The Python module against the engine and the CLI: scenes from files and dicts, check(),
stepping, whole runs and their files, errors, the GIL and Ctrl-C.

Run from the repository root or from python/: ``pytest python/tests``. The CLI comparisons use
the ``wetbounce`` binary of ``$WETBOUNCE_BIN``, else ``target/debug/wetbounce`` or
``target/release/wetbounce`` when built, and are skipped without one.
"""

from __future__ import annotations

import csv
import json
import math
import os
import signal
import subprocess
import threading
import time
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import wetbounce as wb

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
TOLUENE = SCENES / "toluene_drop.toml"
GLASS = SCENES / "glass_bead.toml"
HEAP = SCENES / "heap.toml"


def cli() -> Path | None:
    """The CLI binary to compare with, if one is built."""
    env = os.environ.get("WETBOUNCE_BIN")
    if env:
        assert Path(env).exists(), f"WETBOUNCE_BIN={env} does not exist"
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        p = target / profile / "wetbounce"
        if p.exists():
            return p
    return None


def bad_scenes() -> list[tuple[Path, list[str]]]:
    """scenes/bad/*.toml with their `# expect:` substrings (tests/input/scenes_bad.rs)."""
    out = []
    for p in sorted((SCENES / "bad").glob("*.toml")):
        expected = []
        for line in p.read_text().splitlines():
            if not line.startswith("# expect: "):
                break
            expected.append(line.removeprefix("# expect: ").rstrip())
        out.append((p, expected))
    assert len(out) >= 30
    return out


# --- scenes -------------------------------------------------------------------------------


def test_load_and_check_give_the_cli_report_as_data():
    scene = wb.Scene.load(TOLUENE)
    assert scene.path == Path(TOLUENE)
    assert scene.duration == 1.0 and scene.dt == 1e-4
    report = scene.check()
    assert report["file"] == str(TOLUENE)
    assert report["walls"] == ["top"] and report["integrator"] == "rk2"
    assert report["bounce"]["st_critical"] == 10.0
    kinds = pd.DataFrame(report["kinds"])
    assert list(kinds["kind"]) == ["toluene"]
    row = kinds.iloc[0]
    # README's `wetbounce check scenes/toluene_drop.toml`: 2.75 mm, V_t 0.0822, St 38.34,
    # eps 0.365, t_c 25.55 ms, rises.
    assert row["diameter"] == pytest.approx(2.75e-3)
    assert row["terminal_velocity"] == pytest.approx(0.0822, abs=1e-4)
    assert row["stokes"] == pytest.approx(38.34, abs=0.01)
    assert row["eps"] == pytest.approx(0.365, abs=1e-3)
    assert row["contact_time"] == pytest.approx(25.55e-3, abs=1e-5)
    assert bool(row["rising"]) and bool(row["bounces"])


def test_check_numbers_match_the_cli_table():
    exe = cli()
    if exe is None:
        pytest.skip("no wetbounce binary built")
    text = subprocess.run([exe, "check", TOLUENE], capture_output=True, text=True, check=True).stdout
    line = next(l for l in text.splitlines() if l.strip().startswith("toluene"))
    fields = line.split()
    k = wb.Scene.load(TOLUENE).check()["kinds"][0]
    assert fields[1] == f"{k['diameter'] * 1e3:.4f}"
    assert fields[2] == f"{k['terminal_velocity']:.4f}"
    assert fields[4] == f"{k['stokes']:.2f}"
    assert fields[6] == f"{k['contact_time'] * 1e3:.4f}"


def test_every_bad_scene_raises_the_cli_message():
    exe = cli()
    for path, expected in bad_scenes():
        with pytest.raises(wb.SceneError) as info:
            wb.Scene.load(path)
        e = info.value
        message = str(e)
        assert message.startswith(f"{path}: "), message
        assert e.file == str(path)
        for part in expected:
            assert part in message, (path.name, part, message)
        assert message == f"{e.file}: {e.key}: {e.message}" or e.key == ""
        if exe is not None:
            r = subprocess.run([exe, "check", path], capture_output=True, text=True)
            assert r.returncode != 0
            assert r.stderr.strip() == f"error: {message}", path.name


def test_a_bad_dict_is_refused_like_the_file_and_named_dict():
    checked = 0
    for path, _ in bad_scenes():
        if path.name == "random_fill_too_full.toml":
            continue  # 14 s of placement attempts in a debug build; the file test has it
        try:
            d = tomllib.loads(path.read_text())
        except tomllib.TOMLDecodeError:
            continue  # a TOML syntax error has no dict form
        with pytest.raises(wb.SceneError) as from_dict:
            wb.Scene.from_dict(d, base_dir=path.parent)
        with pytest.raises(wb.SceneError) as from_file:
            wb.Scene.load(path)
        a, b = from_dict.value, from_file.value
        assert a.file == str(path.parent / "<dict>")
        assert a.key == b.key, path.name
        if "line" not in b.message:  # parse errors quote the line of the text they parsed
            assert a.message == b.message, path.name
        checked += 1
    assert checked >= 25


def test_dict_without_base_dir_is_called_dict():
    d = tomllib.loads(TOLUENE.read_text())
    d["kinds"][0]["density"] = -860.0
    with pytest.raises(wb.SceneError, match=r"^<dict>: kinds\[0\]\.density: must be > 0, got -860$"):
        wb.Scene.from_dict(d)


def test_dict_scene_runs_like_the_file():
    a = wb.Scene.load(TOLUENE)
    b = wb.Scene.from_dict(tomllib.loads(TOLUENE.read_text()))
    assert b.path == Path("<dict>")
    sa, sb = a.simulation(), b.simulation()
    sa.advance_to(0.45)
    sb.advance_to(0.45)
    np.testing.assert_array_equal(sa.positions, sb.positions)
    pd.testing.assert_frame_equal(sa.events(), sb.events())


def test_keys_get_set_append_and_remove():
    scene = wb.Scene.load(TOLUENE)
    assert scene["kinds[0].density"] == 860.0
    assert scene["simulation.integrator"] == "rk2"
    changed = scene.with_values({"simulation.duration": 0.25, "kinds[0].restitution_max": np.float64(0.5)})
    assert changed.duration == 0.25 and changed["kinds[0].restitution_max"] == 0.5
    assert scene.duration == 1.0  # scenes are immutable
    # A numpy array becomes a TOML array.
    moved = scene.with_values({"particles[0].position": np.array([0.0, 0.0, -0.01])})
    assert moved["particles[0].position"] == [0.0, 0.0, -0.01]
    with pytest.raises(KeyError):
        scene["simulation.no_such_key"]
    with pytest.raises(KeyError):
        scene.with_values({"kinds[5].density": 1.0})
    with pytest.raises(KeyError):
        scene.with_values({"kinds[0": 1.0})
    # A removed required key is the loader's error, named with the file.
    with pytest.raises(wb.SceneError, match=r"toluene_drop\.toml: .*density"):
        scene.with_values({"kinds[0].density": None})
    with pytest.raises(wb.SceneError, match=r"toluene_drop\.toml: kinds\[0\]\.density: must be > 0"):
        scene.with_values({"kinds[0].density": 0})
    with pytest.raises(TypeError):
        scene.with_values({"simulation.duration": object()})
    assert scene.to_dict() == tomllib.loads(TOLUENE.read_text())


# --- stepping -----------------------------------------------------------------------------


def test_columns_are_numpy_arrays_of_the_right_shapes():
    sim = wb.Scene.load(GLASS).simulation()
    sim.advance_to(0.1)
    assert sim.time == 0.1
    n = len(sim)
    assert sim.positions.shape == (n, 3) and sim.positions.dtype == np.float64
    assert sim.velocities.shape == (n, 3) and sim.velocities.dtype == np.float64
    assert sim.states.dtype == np.uint8 and sim.states.shape == (n,)
    assert sim.ids.dtype == np.uint32 and sim.kinds.dtype == np.uint16
    assert sim.diameters.dtype == np.float64
    assert sim.kind_names == ["glass"] or len(sim.kind_names) == 1
    assert wb.STATE_NAMES == ("free", "held", "resting")
    # The bead settles (z decreases) at first.
    assert sim.velocities[0, 2] < 0


def test_advance_to_refuses_going_back_and_non_finite_times():
    sim = wb.Scene.load(TOLUENE).simulation()
    sim.advance_to(0.01)
    with pytest.raises(ValueError, match="before"):
        sim.advance_to(0.005)
    with pytest.raises(ValueError, match="finite"):
        sim.advance_to(math.nan)


def test_stepping_to_output_times_gives_the_run_files_rows(tmp_path):
    """advance_to(t) at output times gives, bit for bit, the rows of trajectories.csv."""
    scene = wb.Scene.load(TOLUENE).with_values({"simulation.output_interval": 0.05})
    sim = scene.simulation()
    assert sim.run(tmp_path, formats=["csv"], quiet=True) is sim  # run() returns the simulation
    assert {p.name for p in sim.files} == {"trajectories.csv", "events.csv", "summary.json"}
    rows = list(csv.DictReader(open(tmp_path / "trajectories.csv")))
    sim = scene.simulation()
    compared = 0
    for r in rows:
        t = float(r["t"])
        sim.advance_to(t)
        assert sim.time == t
        pos, vel = sim.positions[0], sim.velocities[0]
        assert [float(r[k]) for k in ("x", "y", "z")] == list(pos)
        assert [float(r[k]) for k in ("vx", "vy", "vz")] == list(vel)
        assert r["state"] == wb.STATE_NAMES[sim.states[0]]
        compared += 1
    assert compared == 21
    events = pd.read_csv(tmp_path / "events.csv", keep_default_na=False)
    mine = sim.events()
    assert list(mine.columns) == list(events.columns)
    assert len(mine) == len(events) == 3
    np.testing.assert_array_equal(mine["t"], events["t"])
    assert list(mine["outcome"]) == ["held", "held", "deposited"]
    assert list(mine["other"]) == list(events["other"].astype(str))


def short_heap() -> wb.Scene:
    """scenes/heap.toml (friction, so rotation) cut to its first 0.3 s: the first beads land
    at about 0.13 s, the later ones on them, obliquely, and spin."""
    return wb.Scene.load(HEAP).with_values({"simulation.duration": 0.3, "simulation.output_interval": 0.05})


def test_spin_in_a_scene_with_rotation_is_the_cli_files(tmp_path):
    """angular_velocities at output times are trajectories.csv's wx, wy, wz, bit for bit, and
    events() has events.csv's tangential_speed and incidence_angle; the files are the CLI's."""
    scene = short_heap()
    scene.run(tmp_path / "py", formats=["csv"])
    exe = cli()
    if exe is not None:
        # The CLI has no --duration: it runs the cut scene's text.
        path = tmp_path / "heap_short.toml"
        path.write_text(scene.source)
        subprocess.run(
            [exe, "run", path, "--out", tmp_path / "cli", "--formats", "csv", "--quiet"],
            check=True,
            capture_output=True,
        )
        for name in ("trajectories.csv", "events.csv"):
            assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    files = tmp_path / ("cli" if exe is not None else "py")

    trajectories = pd.read_csv(files / "trajectories.csv")
    assert list(trajectories.columns)[-4:] == ["state", "wx", "wy", "wz"]
    sim = scene.simulation()
    frames = 0
    for t, rows in trajectories.groupby("t", sort=True):
        sim.advance_to(t)
        assert sim.time == t
        omega = sim.angular_velocities
        assert omega.shape == (len(sim), 3) and omega.dtype == np.float64
        rows = rows.set_index("id").loc[sim.ids]
        np.testing.assert_array_equal(omega, rows[["wx", "wy", "wz"]].to_numpy())
        np.testing.assert_array_equal(sim.velocities, rows[["vx", "vy", "vz"]].to_numpy())
        frames += 1
    assert frames == 6  # 0.05 s to 0.3 s: at t = 0 no bead is in yet, so no rows
    spinning = np.linalg.norm(sim.angular_velocities, axis=1) > 0
    assert spinning.sum() >= 10, spinning.sum()

    events = pd.read_csv(files / "events.csv", keep_default_na=False)
    mine = sim.events()
    assert list(mine.columns) == list(events.columns)
    assert list(mine.columns)[-2:] == ["tangential_speed", "incidence_angle"]
    assert len(mine) == len(events) > 0
    for column in ("t", "normal_speed", "tangential_speed", "incidence_angle"):
        np.testing.assert_array_equal(mine[column], events[column].astype(float), err_msg=column)
    assert list(mine["other"]) == list(events["other"].astype(str))
    # Oblique impacts on the pile: a tangential speed, an angle from the normal.
    assert (mine["tangential_speed"] > 0).any() and (mine["incidence_angle"] > 0).any()
    assert mine["incidence_angle"].between(0.0, math.pi).all()


def test_no_spin_columns_without_rotation():
    sim = wb.Scene.load(GLASS).simulation()
    sim.advance_to(0.3)  # the bead has hit the floor (at about 0.2 s)
    events = sim.events()
    assert len(events) > 0
    assert list(events.columns) == [
        "t", "id", "other", "kind", "normal_speed", "st", "eps", "contact_time", "outcome",
    ]
    # The engine never computes the spin there: exactly zero.
    assert sim.angular_velocities.shape == (len(sim), 3)
    assert sim.angular_velocities.dtype == np.float64
    assert not sim.angular_velocities.any()


# --- whole runs ---------------------------------------------------------------------------


def test_run_writes_the_cli_files(tmp_path):
    sim = wb.Scene.load(TOLUENE).run(tmp_path / "py", formats=["mcap", "csv"])
    out = tmp_path / "py"
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "events.csv", "summary.json", "toluene_drop.mcap", "toluene_drop_foxglove_layout.json", "trajectories.csv",
    ]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["interrupted"] is False and summary["signal"] is None
    assert summary["output_errors"] == []
    assert summary["impacts"]["total"] == 3 and summary["impacts"]["held"] == 2
    assert summary["scene"] == str(TOLUENE)
    mine = sim.summary()
    for key in ("impacts", "particles", "walls", "outlets", "steps", "time_s"):
        assert mine[key] == summary[key]
    walls = sim.summary_frames()["walls"]
    assert walls.loc["top", "impacts"] == 3
    exe = cli()
    if exe is None:
        return
    subprocess.run(
        [exe, "run", TOLUENE, "--out", tmp_path / "cli", "--formats", "mcap,csv", "--quiet"],
        check=True,
        capture_output=True,
    )
    for name in ("trajectories.csv", "events.csv", "toluene_drop_foxglove_layout.json"):
        assert (out / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    for d in (summary, cli_summary):
        d.pop("wall_time_s")
    assert summary == cli_summary


def test_a_run_with_an_outlet_gives_residence_times():
    # The column, short: 20 drops, an outlet 10 cm up.
    scene = wb.Scene.load(SCENES / "column.toml").with_values(
        {
            "injectors[0].rate": 100.0,
            "injectors[0].stop": 0.2,
            "outlets[0].point": [0.0, 0.0, 0.1],
            "simulation.duration": 2.5,
        }
    )
    sim = scene.simulation()
    sim.advance_to(scene.duration)
    assert sim.summary()["particles"]["injected"] == 20
    rt = sim.residence_times()
    assert list(rt.columns) == ["outlet", "id", "t", "residence_time"]
    assert len(rt) > 0 and (rt["residence_time"] > 0).all()
    outlets = sim.summary_frames()["outlets"]
    assert outlets.iloc[0]["count"] == len(rt)
    assert outlets.iloc[0]["mean"] == pytest.approx(rt["residence_time"].mean())


def test_save_and_load_go_on_exactly_through_injections_and_an_outlet(tmp_path):
    # The short column of the test above: drops injected, some taken out by the outlet.
    scene = wb.Scene.load(SCENES / "column.toml").with_values(
        {
            "injectors[0].rate": 100.0,
            "injectors[0].stop": 0.5,
            "outlets[0].point": [0.0, 0.0, 0.02],
            "simulation.duration": 1.2,
        }
    )
    a = scene.simulation()
    a.advance_to(0.3137)
    a.save(tmp_path / "cut.wbck")
    b = wb.Simulation.load(tmp_path / "cut.wbck")
    assert b.time == a.time and len(b) == len(a)
    a.advance_to(1.2)
    b.advance_to(1.2)
    assert np.array_equal(a.ids, b.ids)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
    assert a.summary()["particles"] == b.summary()["particles"]
    assert a.residence_times()["residence_time"].tolist() == b.residence_times()["residence_time"].tolist()
    (tmp_path / "bad.wbck").write_bytes(b"not a checkpoint")
    with pytest.raises(ValueError, match="bad.wbck: not a wetbounce checkpoint"):
        wb.Simulation.load(tmp_path / "bad.wbck")


def test_summary_frames_give_nan_not_none_where_nothing_was_measured():
    """Before any drop leaves, the outlet's statistics are NaN in float columns (pandas'
    missing value), not None in object columns; the same for a wall without impacts."""
    scene = wb.Scene.load(SCENES / "column.toml")
    sim = scene.simulation()
    sim.advance_to(0.01)
    outlets = sim.summary_frames()["outlets"]
    assert outlets.iloc[0]["count"] == 0
    for column in ("mean", "min", "p10", "p50", "p90", "max"):
        assert outlets[column].dtype == np.float64, (column, outlets[column].dtype)
        assert math.isnan(outlets.iloc[0][column]), column
    walls = sim.summary_frames()["walls"]
    assert walls["mean_st"].dtype == np.float64 and walls["mean_st"].isna().all()


def test_run_only_from_time_zero(tmp_path):
    sim = wb.Scene.load(TOLUENE).simulation()
    sim.advance_to(0.01)
    with pytest.raises(RuntimeError, match="t = 0"):
        sim.run(tmp_path)


def test_bad_formats_and_unwritable_files_raise(tmp_path):
    scene = wb.Scene.load(TOLUENE)
    with pytest.raises(ValueError, match='formats: "hdf5" is not one of "mcap", "csv", "rrd", "vtk"'):
        scene.run(tmp_path, formats=["hdf5"])
    (tmp_path / "trajectories.csv").mkdir()
    with pytest.raises(wb.OutputError) as info:
        scene.run(tmp_path, formats=["csv"])
    assert "trajectories.csv" in str(info.value)
    assert isinstance(info.value, OSError)
    # A folder that cannot be created (inside a file) is an OutputError naming it too.
    (tmp_path / "a_file").write_text("x")
    with pytest.raises(wb.OutputError, match="cannot create the output folder") as info:
        scene.run(tmp_path / "a_file" / "out", formats=["csv"])
    assert info.value.files == [str(tmp_path / "a_file" / "out")]


def test_vtk_files_are_the_cli_files_and_a_rerun_removes_the_stale_ones(tmp_path):
    """formats=["vtk"] writes what ``wetbounce run --formats vtk`` writes, byte for byte (one
    output folder for both, ``output::Folder``); a rerun in other formats removes them."""
    scene = wb.Scene.load(TOLUENE).with_values({"simulation.duration": 0.2, "simulation.output_interval": 0.05})
    written = scene.simulation().run(tmp_path / "py", formats=["vtk"], name="drop").files
    names = sorted(p.name for p in written)
    assert names == ["drop.pvd", "drop_walls.vtp", "events.csv", "summary.json"], names
    frames = sorted(p.name for p in (tmp_path / "py" / "drop_vtk").iterdir())
    assert frames == [f"particles_{k:06}.vtp" for k in range(5)], frames
    exe = cli()
    if exe is not None:
        path = tmp_path / "drop.toml"
        path.write_text(scene.source)
        subprocess.run([exe, "run", path, "--out", tmp_path / "cli", "--formats", "vtk", "--quiet"],
                       check=True, capture_output=True)
        for rel in ["drop.pvd", "drop_walls.vtp", "events.csv", *(f"drop_vtk/{f}" for f in frames)]:
            assert (tmp_path / "py" / rel).read_bytes() == (tmp_path / "cli" / rel).read_bytes(), rel
    scene.simulation().run(tmp_path / "py", formats=["csv"], name="drop")
    assert not (tmp_path / "py" / "drop.pvd").exists()
    assert not (tmp_path / "py" / "drop_vtk").exists()


# --- the GIL and Ctrl-C -------------------------------------------------------------------


def long_scene() -> wb.Scene:
    """The settling bed: 2000 beads, seconds of work per simulated second."""
    return wb.Scene.load(SCENES / "settling_bed.toml")


def test_the_gil_is_released_while_stepping():
    """Counts work done by another Python thread *during one* ``advance_to`` call, whatever the
    machine's speed: the counting thread needs the GIL for each tick, and once it has ticked
    200 times it stops the run with SIGINT. With the GIL held by the engine it could not tick
    at all, the call would run to its end (a minute of simulated time) or to the alarm, and the
    test fails either way. (It used to assume that a run takes over 0.2 s: a release build took
    0.02 s.)"""
    sim = long_scene().with_values({"simulation.duration": 60.0}).simulation()
    ticks = 0

    def count():
        nonlocal ticks
        while ticks < 200:
            ticks += 1
            time.sleep(0.0005)
        os.kill(os.getpid(), signal.SIGINT)

    def give_up(signum, frame):
        raise TimeoutError("the counting thread never ran while the engine stepped")

    previous = signal.signal(signal.SIGALRM, give_up)
    signal.alarm(120)
    counter = threading.Thread(target=count)
    try:
        counter.start()
        with pytest.raises(KeyboardInterrupt):
            sim.advance_to(sim.duration)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    counter.join()
    assert ticks == 200
    assert 0 < sim.time < sim.duration


def interrupt_after(seconds: float) -> threading.Timer:
    t = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    t.start()
    return t


def test_ctrl_c_stops_advance_to_and_leaves_a_usable_simulation():
    sim = long_scene().simulation()
    timer = interrupt_after(0.3)
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        sim.advance_to(sim.duration)
    timer.join()
    assert time.perf_counter() - start < 5.0
    t = sim.time
    assert 0 < t < sim.duration
    sim.advance_to(t + sim.dt)  # still usable
    assert sim.time == pytest.approx(t + sim.dt)


def test_ctrl_c_stops_a_run_and_closes_its_files(tmp_path):
    scene = long_scene()
    sim = scene.simulation()
    timer = interrupt_after(0.5)
    with pytest.raises(KeyboardInterrupt):
        sim.run(tmp_path, formats=["mcap", "csv"])
    timer.join()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["interrupted"] is True and summary["signal"] == "SIGINT"
    assert 0 < summary["time_s"] < scene.duration
    # The last frame is at the time the run stopped.
    last = pd.read_csv(tmp_path / "trajectories.csv")["t"].iloc[-1]
    assert last == summary["time_s"]
    assert (tmp_path / "settling_bed.mcap").stat().st_size > 0


# --- stubs --------------------------------------------------------------------------------


def test_the_stubs_name_what_the_module_has():
    """Every class and method of _wetbounce.pyi exists, and every public one is in the stubs."""
    import ast

    import wetbounce._wetbounce as ext

    tree = ast.parse((Path(wb.__file__).parent / "_wetbounce.pyi").read_text())
    stub_classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    for name, node in stub_classes.items():
        cls = getattr(ext, name)
        stubbed = {f.name for f in node.body if isinstance(f, ast.FunctionDef)}
        public = {m for m in vars(cls) if not m.startswith("_")}
        assert stubbed - {"__getitem__", "__len__"} >= public or name.endswith("Error"), (name, public - stubbed)
        for m in stubbed:
            assert hasattr(cls, m), (name, m)
        assert cls.__doc__, name
        for m in public:
            assert getattr(cls, m).__doc__, (name, m)
    assert {"Scene", "Simulation", "SceneError", "OutputError"} <= set(stub_classes)


def test_particles_is_a_frame_of_trajectories_csv_with_kind_and_diameter(tmp_path):
    """Simulation.particles() at an output time holds the rows trajectories.csv has for it."""
    scene = short_heap()
    scene.run(tmp_path, formats=["csv"])
    trajectories = pd.read_csv(tmp_path / "trajectories.csv")
    sim = scene.simulation()
    for t in sorted(trajectories["t"].unique()):  # the CLI's steps: every output time in turn
        sim.advance_to(t)
    assert sim.time == 0.3
    now = sim.particles()
    assert list(now.columns) == ["id", "kind", "diameter", "x", "y", "z", "vx", "vy", "vz", "state", "wx", "wy", "wz"]
    assert len(now) == len(sim) > 0
    rows = trajectories[trajectories["t"] == 0.3].set_index("id").loc[now["id"]]
    for column in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"):
        np.testing.assert_array_equal(now[column].to_numpy(), rows[column].to_numpy(), err_msg=column)
    assert list(now["state"]) == list(rows["state"])
    assert set(now["kind"]) <= set(sim.kind_names)
    np.testing.assert_array_equal(now["diameter"].to_numpy(), sim.diameters)
    # Without rotation there are no spin columns, as in trajectories.csv.
    plain = wb.Scene.load(TOLUENE).simulation().particles()
    assert list(plain.columns)[-1] == "state"


def test_scene_and_simulation_show_a_summary_table_in_jupyter():
    scene = wb.Scene.load(TOLUENE)
    html = scene._repr_html_()
    assert html.startswith("<table>") and "toluene_drop.toml" in html and "rk2" in html
    sim = scene.simulation()
    sim.advance_to(0.1)
    html = sim._repr_html_()
    assert "0.1 s of 1 s" in html and "1: " in html and "</table>" in html


def test_record_gives_the_trajectories_csv_rows_as_a_long_frame(tmp_path):
    """record(the output times) holds the rows of trajectories.csv, t first; times before the
    simulation's are refused."""
    scene = short_heap()
    scene.run(tmp_path, formats=["csv"], quiet=True)
    trajectories = pd.read_csv(tmp_path / "trajectories.csv")
    times = sorted(trajectories["t"].unique())
    sim = scene.simulation()
    long = sim.record(times)
    assert list(long.columns)[:2] == ["t", "id"]
    assert len(long) == len(trajectories)
    mine = long.sort_values(["t", "id"]).reset_index(drop=True)
    theirs = trajectories.sort_values(["t", "id"]).reset_index(drop=True)
    for column in ("t", "id", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"):
        np.testing.assert_array_equal(mine[column].to_numpy(), theirs[column].to_numpy(), err_msg=column)
    assert list(mine["state"]) == list(theirs["state"])
    with pytest.raises(ValueError, match=r"times\[0\] = 0.1 s is before"):
        sim.record([0.1])
    assert len(sim.record([])) == 0


def test_scene_run_and_simulation_run_both_return_the_finished_simulation(tmp_path):
    scene = wb.Scene.load(TOLUENE).with_values({"simulation.duration": 0.1})
    a = scene.run(tmp_path / "a", formats=["csv"], quiet=True)
    b = scene.simulation()
    assert b.run(tmp_path / "b", formats=["csv"], quiet=True) is b
    assert isinstance(a, wb.Simulation) and a.time == b.time == 0.1
    assert [p.name for p in a.files] == [p.name for p in b.files]
    assert scene.simulation().files == []


def test_a_progress_bar_is_drawn_unless_quiet(capfd):
    """tqdm's bar when tqdm is installed (CI installs it), on standard error; none with
    quiet=True."""
    pytest.importorskip("tqdm")
    scene = wb.Scene.load(TOLUENE).with_values({"simulation.duration": 0.2})
    scene.run(quiet=True)
    assert capfd.readouterr().err == ""
    scene.run()
    err = capfd.readouterr().err
    assert "simulated" in err and "100%" in err and "0.2/0.2 s" in err, err

