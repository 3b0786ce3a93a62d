#!/usr/bin/env bash
# A run on ranks checkpoints, and its checkpoint resumes on any number of ranks — one process
# included — to the files of a run never stopped (docs/distributed.md, "Checkpoints"):
#
#     bash tools/ranks_resume.sh [SCENE] [T]     # default: the column, checkpoint at T = 8 s
#
# 1. the scene on one process, whole: the reference;
# 2. on 2 ranks with a checkpoint at T (--checkpoint-every T), to its end;
# 3. from that checkpoint, resumed on 3 ranks and on one process into new folders.
# Every output of 3. must be the reference's bytes (summary.json but its wall time). Needs a build
# with `--features mpi` (WETBOUNCE=path, default target/release/wetbounce) and mpirun.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/column.toml}
at=${2:-8}
bin=${WETBOUNCE:-target/release/wetbounce}
stem=$(basename "$scene" .toml)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
root=()
[ "$(id -u)" = 0 ] && root=(--allow-run-as-root)
mpi() { local k=$1; shift; mpirun "${root[@]}" --oversubscribe -np "$k" "$bin" "$@"; }
"$bin" run "$scene" --out "$out/one" --formats mcap,csv --quiet >/dev/null
mpi 2 run "$scene" --out "$out/two" --formats mcap,csv --quiet --checkpoint-every "$at" --checkpoint-keep 3 >/dev/null
checkpoint=$(ls "$out"/two/checkpoints/checkpoint-*.wbck | head -1)
mpi 3 resume "$checkpoint" --out "$out/three" --quiet >/dev/null
"$bin" resume "$checkpoint" --out "$out/alone" --quiet >/dev/null
failed=0
for run in three alone; do
  for f in "$out/one"/*; do
    name=$(basename "$f")
    [ -d "$f" ] && continue
    g="$out/$run/$name"
    if [ "$name" = summary.json ]; then
      cmp -s <(grep -v '"wall_time_s"' "$f") <(grep -v '"wall_time_s"' "$g") || { echo "DIFFER $run: $name"; failed=1; }
    elif [ "$name" = "$stem.mcap" ]; then
      # A resumed MCAP goes on in <stem>.part2.mcap: the trajectories are compared through the CSV.
      [ -f "$out/$run/$stem.part2.mcap" ] || { echo "MISSING $run: $stem.part2.mcap"; failed=1; }
    else
      cmp -s "$f" "$g" || { echo "DIFFER $run: $name"; failed=1; }
    fi
  done
done
[ $failed = 0 ] && echo "same: $stem checkpointed at t = $at s on 2 ranks, resumed on 3 ranks and on one process"
exit $failed
