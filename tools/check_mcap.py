#!/usr/bin/env python3
"""Checks a shipped scene's MCAP with the viewers' own tools, independently of the Rust tests.

1. Runs `wetbounce run SCENE --formats mcap,csv` into a temporary folder.
2. Reads the MCAP with the Python `mcap` library and decodes every message with the schema
   stored in the file (`mcap-protobuf-support` for Foxglove's protobuf schemas, `json` for
   /events): channel names and schemas, one /particles message per CSV frame, monotonic log
   times, the same positions as trajectories.csv.
3. Runs `rerun mcap convert` (the `rerun-sdk` package's CLI) and `rerun rrd print`, and
   asserts that /particles became Points3D positions, one row per frame.

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
        clouds, last_time, n_events = [], {}, 0
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
            elif topic in ("/scene", "/walls"):
                check(len(decoded.entities) > 0, "empty SceneUpdate")
        check(len(clouds) == len(rows), f"{len(clouds)} points, {len(rows)} CSV rows")
        for (t_ns, xyz), row in zip(clouds, rows):
            check(t_ns == round(float(row["t"]) * 1e9), f"time {t_ns} ns vs {row['t']} s")
            check(xyz == [float(row[a]) for a in "xyz"], f"position {xyz} vs {row}")
        check(n_events == len(events), f"{n_events} /events messages, {len(events)} CSV rows")
    frames = len({r["t"] for r in rows})
    print(f"check_mcap: {path.name}: channels, schemas, {frames} frames and {n_events} events match the CSV")
    return frames


def check_with_rerun(path, frames, rerun):
    rrd = path.with_suffix(".converted.rrd")
    env = dict(os.environ, RERUN_ANALYTICS="0")
    done = subprocess.run([rerun, "mcap", "convert", str(path), "-o", str(rrd)], capture_output=True, text=True, env=env)
    check(done.returncode == 0, f"rerun mcap convert exited {done.returncode}: {done.stderr}")
    done = subprocess.run([rerun, "rrd", "print", str(rrd)], capture_output=True, text=True, env=env)
    check(done.returncode == 0, f"rerun rrd print exited {done.returncode}: {done.stderr}")
    # Lines like "Chunk(...) with 1001 rows (110 KiB) - /particles - data columns: [... Points3D:positions]"
    rows = 0
    for line in done.stdout.splitlines():
        m = re.search(r"with (\d+) rows .* - /particles - data columns: \[(.*)\]", line)
        if m and "Points3D:positions" in m.group(2):
            rows += int(m.group(1))
    check(rows == frames, f"rerun turned /particles into {rows} rows of Points3D positions, expected {frames}:\n{done.stdout}")
    print(f"check_mcap: rerun mcap convert: /particles became Points3D positions, {rows} frames")


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
    print("check_mcap: OK")


if __name__ == "__main__":
    main()
