#!/usr/bin/env bash
# Runs shipped scenes on 1 rank and on K ranks (`mpirun -np K`, oversubscribed) and checks that
# every output file — MCAP, CSV, the ParaView frames — is byte-identical (summary.json without
# its wall time, which differs between any two runs): the promise of docs/distributed.md.
#
#     bash tools/ranks_same.sh 2 3 -- scenes/column.toml scenes/heap.toml
#     bash tools/ranks_same.sh 2                       # every shipped scene on 2 ranks
#
# Needs a build with `--features mpi` (WETBOUNCE=path picks the binary, default
# target/release/wetbounce) and Open MPI's mpirun. Prints one line per scene and rank count;
# exits 1 if any file differs. As root (CI, containers) mpirun needs --allow-run-as-root, which
# this script passes.
set -euo pipefail
cd "$(dirname "$0")/.."
counts=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do counts+=("$1"); shift; done
[ $# -gt 0 ] && shift
scenes=("$@")
[ ${#counts[@]} -gt 0 ] || counts=(2)
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/*.toml)
bin=${WETBOUNCE:-target/release/wetbounce}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
root=()
[ "$(id -u)" = 0 ] && root=(--allow-run-as-root)
failed=0
same() {
  if [ "$(basename "$1")" = summary.json ]; then
    cmp -s <(grep -v '"wall_time_s"' "$1") <(grep -v '"wall_time_s"' "$2")
  elif [ -d "$1" ]; then
    diff -rq "$1" "$2" >/dev/null
  else
    cmp -s "$1" "$2"
  fi
}
for scene in "${scenes[@]}"; do
  stem=$(basename "$scene" .toml)
  start=$(date +%s%N)
  "$bin" run "$scene" --out "$out/$stem-1" --formats mcap,csv,vtk --quiet >/dev/null
  one=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { print (b - a) / 1e9 }')
  for k in "${counts[@]}"; do
    start=$(date +%s%N)
    if ! mpirun "${root[@]}" --oversubscribe -np "$k" "$bin" run "$scene" --out "$out/$stem-$k" \
        --formats mcap,csv,vtk --quiet >"$out/$stem-$k.txt" 2>&1; then
      echo "FAILED  $stem on $k ranks:"; tail -5 "$out/$stem-$k.txt"; failed=1; continue
    fi
    many=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { print (b - a) / 1e9 }')
    differ=()
    for f in "$out/$stem-1"/*; do
      same "$f" "$out/$stem-$k/$(basename "$f")" || differ+=("$(basename "$f")")
    done
    split=$(grep '^clusters:' "$out/$stem-$k.txt" || true)
    if [ ${#differ[@]} -eq 0 ]; then
      printf 'same    %-40s 1 rank %6.1f s, %d ranks %6.1f s; %s\n' "$stem" "$one" "$k" "$many" "$split"
    else
      printf 'DIFFER  %-40s on %d ranks: %s\n' "$stem" "$k" "${differ[*]}"; failed=1
    fi
  done
done
exit $failed
