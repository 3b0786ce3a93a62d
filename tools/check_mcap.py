#!/usr/bin/env python3
"""Checks a shipped scene's MCAP with the viewers' own tools, independently of the Rust tests.

1. Runs `wetbounce run SCENE --formats mcap,csv` into a temporary folder.
2. Reads the MCAP with the Python `mcap` library and decodes every message with the schema
   stored in the file (`mcap-protobuf-support` for Foxglove's protobuf schemas, `json` for
   /events): channel names and schemas, one /particles message per CSV frame, monotonic log
   times, the same positions as trajectories.csv, one /event_log line per events.csv row.
3. Runs `rerun mcap convert` (the `rerun-sdk` package's CLI) and `rerun rrd print`, and
   asserts that /particles became Points3D positions, one row per frame.
4. A run in two parts: the scene run to half its duration with a checkpoint at the end, then
   `wetbounce resume --scene` to its whole duration, which writes `<stem>.part2.mcap`. The two
   parts read with the `mcap` library hold one /particles message per frame of the whole
   trajectories.csv, in increasing time; converted by `rerun mcap convert` with one
   `--recording-id` and merged by `rerun rrd merge`, they are one recording with as many
   Points3D rows (docs/output.md, "Checkpoints").

Needs: pip install -r tools/check_mcap.requirements.txt (mcap, mcap-protobuf-support,
rerun-sdk). Usage: python3 tools/check_mcap.py [--wetbounce target/debug/wetbounce]
[--scene scenes/toluene_drop.toml]. Exits non-zero with a message on the first failure.
"""

import argparse
import csv
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

from mcap.decoder import DecoderFactory
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory as ProtobufDecoderFactory

ROOT = Path(__file__).resolve().parent.parent
EXPECTED = {
    "/particles": ("foxglove.PointCloud", "protobuf", "protobuf"),
    "/walls": ("foxglove.SceneUpdate", "protobuf", "protobuf"),
    "/scene": ("foxglove.SceneUpdate", "protobuf", "protobuf"),
    "/events": ("wetbounce.ContactEvent", "jsonschema", "json"),
    "/event_log": ("foxglove.Log", "protobuf", "protobuf"),
}


class JsonDecoderFactory(DecoderFactory):
    """Decodes the JSON channel (/events)."""

    def decoder_for(self, message_encoding, schema):
        return json.loads if message_encoding == "json" else None


def fail(message):
    print(f"check_mcap: FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def run_scene(wetbounce, scene, out):
    cmd = [str(wetbounce), "run", str(scene), "--formats", "mcap,csv", "--quiet", "--out", str(out)]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    check(done.returncode == 0, f"{' '.join(cmd)} exited {done.returncode}: {done.stderr}")
    return out / f"{scene.stem}.mcap"


def check_with_mcap_library(path, out):
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[ProtobufDecoderFactory(), JsonDecoderFactory()])
        summary = reader.get_summary()
        channels = {
            c.topic: (summary.schemas[c.schema_id].name, summary.schemas[c.schema_id].encoding, c.message_encoding)
            for c in summary.channels.values()
        }
        check(channels == EXPECTED, f"channels {channels}, expected {EXPECTED}")
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
        check("source" in metadata.get("scene", {}), "no scene source in the metadata")
        check("version" in metadata.get("wetbounce", {}), "no wetbounce version in the metadata")

        rows = list(csv.DictReader(open(out / "trajectories.csv")))
        events = list(csv.DictReader(open(out / "events.csv")))
        clouds, last_time, n_events, log_lines = [], {}, 0, []
        for schema, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            topic = channel.topic
            check(message.log_time >= last_time.get(topic, 0), f"{topic}: log time goes back")
            last_time[topic] = message.log_time
            if topic == "/particles":
                fields = {f.name: f.offset for f in decoded.fields}
                for k in range(len(decoded.data) // decoded.point_stride):
                    base = k * decoded.point_stride
                    xyz = [struct.unpack_from("<d", decoded.data, base + fields[a])[0] for a in "xyz"]
                    clouds.append((message.log_time, xyz))
            elif topic == "/events":
                event = decoded
                check(set(event) == set(events[0].keys()), f"event fields {sorted(event)}")
                n_events += 1
            elif topic == "/event_log":
                log_lines.append((message.log_time, decoded.level, decoded.message))
            elif topic in ("/scene", "/walls"):
                check(len(decoded.entities) > 0, "empty SceneUpdate")
        check(len(clouds) == len(rows), f"{len(clouds)} points, {len(rows)} CSV rows")
        for (t_ns, xyz), row in zip(clouds, rows):
            check(t_ns == round(float(row["t"]) * 1e9), f"time {t_ns} ns vs {row['t']} s")
            check(xyz == [float(row[a]) for a in "xyz"], f"position {xyz} vs {row}")
        check(n_events == len(events), f"{n_events} /events messages, {len(events)} CSV rows")
        # The Log panel's lines: one per contact, at its time, naming its particle and outcome.
        check(len(log_lines) == len(events), f"{len(log_lines)} /event_log lines, {len(events)} events")
        for (t_ns, level, text), event in zip(log_lines, events):
            check(t_ns == round(float(event["t"]) * 1e9), f"/event_log at {t_ns} ns vs {event['t']} s")
            check(text.startswith(f"particle {event['id']} {event['outcome']} on "), f"/event_log line {text!r}")
            check(level == (3 if event["outcome"] == "deposited" else 2), f"level {level} of {text!r}")
    frames = len({r["t"] for r in rows})
    print(f"check_mcap: {path.name}: channels, schemas, {frames} frames and {n_events} events match the CSV")
    return frames


def particle_rows(rerun, rrd, env):
    """Rows of Points3D positions on /particles in a recording (`rerun rrd print`), and the print."""
    done = subprocess.run([rerun, "rrd", "print", str(rrd)], capture_output=True, text=True, env=env)
    check(done.returncode == 0, f"rerun rrd print exited {done.returncode}: {done.stderr}")
    # Lines like "Chunk(...) with 1001 rows (110 KiB) - /particles - data columns: [... Points3D:positions]"
    rows = 0
    for line in done.stdout.splitlines():
        m = re.search(r"with (\d+) rows .* - /particles - data columns: \[(.*)\]", line)
        if m and "Points3D:positions" in m.group(2):
            rows += int(m.group(1))
    return rows, done.stdout


def check_with_rerun(path, frames, rerun):
    rrd = path.with_suffix(".converted.rrd")
    env = dict(os.environ, RERUN_ANALYTICS="0")
    done = subprocess.run([rerun, "mcap", "convert", str(path), "-o", str(rrd)], capture_output=True, text=True, env=env)
    check(done.returncode == 0, f"rerun mcap convert exited {done.returncode}: {done.stderr}")
    rows, printed = particle_rows(rerun, rrd, env)
    check(rows == frames, f"rerun turned /particles into {rows} rows of Points3D positions, expected {frames}:\n{printed}")
    print(f"check_mcap: rerun mcap convert: /particles became Points3D positions, {rows} frames")


def check_resumed_parts(wetbounce, scene, rerun, tmp):
    """Item 4 of the module doc: a run in two parts opens as one in the viewers' readers."""
    text = scene.read_text() if scene.is_absolute() else (ROOT / scene).read_text()
    m = re.search(r"(?m)^duration\s*=\s*([0-9.eE+-]+)", text)
    check(m is not None, f"{scene}: no duration line")
    half = float(m.group(1)) / 2
    first = tmp / f"{scene.stem}.toml"
    first.write_text(text[: m.start(1)] + repr(half) + text[m.end(1) :])
    whole = tmp / "whole.toml"
    whole.write_text(text)
    out = tmp / "parts"
    cmd = [str(wetbounce), "run", str(first), "--formats", "mcap,csv", "--quiet", "--out", str(out),
           "--checkpoint-every", repr(half)]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    check(done.returncode == 0, f"{' '.join(cmd)} exited {done.returncode}: {done.stderr}")
    checkpoints = sorted((out / "checkpoints").glob("checkpoint-*.wbck"))
    check(len(checkpoints) >= 1, f"no checkpoint in {out}/checkpoints")
    cmd = [str(wetbounce), "resume", str(checkpoints[-1]), "--scene", str(whole), "--quiet"]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    check(done.returncode == 0, f"{' '.join(cmd)} exited {done.returncode}: {done.stderr}")
    parts = [out / f"{scene.stem}.mcap", out / f"{scene.stem}.part2.mcap"]
    times = []
    for p in parts:
        with open(p, "rb") as f:
            times += [m.log_time for _, ch, m in make_reader(f).iter_messages() if ch.topic == "/particles"]
    with open(out / "trajectories.csv", newline="") as f:
        frames = len({row["t"] for row in csv.DictReader(f)})
    check(len(times) == frames, f"the parts hold {len(times)} /particles messages, trajectories.csv {frames} frames")
    check(all(a < b for a, b in zip(times, times[1:])), "the parts' /particles times do not increase")
    env = dict(os.environ, RERUN_ANALYTICS="0")
    rrds = []
    for p in parts:
        rrd = p.with_suffix(".rrd")
        cmd = [rerun, "mcap", "convert", str(p), "--recording-id", "run", "--application-id", scene.stem, "-o", str(rrd)]
        done = subprocess.run(cmd, capture_output=True, text=True, env=env)
        check(done.returncode == 0, f"{' '.join(cmd)} exited {done.returncode}: {done.stderr}")
        rrds.append(str(rrd))
    merged = out / "merged.rrd"
    done = subprocess.run([rerun, "rrd", "merge", *rrds, "-o", str(merged)], capture_output=True, text=True, env=env)
    check(done.returncode == 0, f"rerun rrd merge exited {done.returncode}: {done.stderr}")
    rows, _ = particle_rows(rerun, merged, env)
    check(rows == frames, f"the merged recording has {rows} rows of /particles, expected {frames}")
    print(f"check_mcap: a run resumed into {parts[1].name}: {frames} frames over both parts, one rerun recording")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wetbounce", default=str(ROOT / "target/debug/wetbounce"))
    parser.add_argument("--scene", default="scenes/toluene_drop.toml")
    parser.add_argument("--rerun", default=shutil.which("rerun") or "rerun")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        path = run_scene(args.wetbounce, Path(args.scene), out)
        frames = check_with_mcap_library(path, out)
        check_with_rerun(path, frames, args.rerun)
        check_resumed_parts(args.wetbounce, Path(args.scene), args.rerun, out)
    print("check_mcap: OK")


if __name__ == "__main__":
    main()
