#!/usr/bin/env bash
# Runs every shipped scene (scenes/*.toml) with MCAP and CSV output and prints one checksum per
# output file, so that a change meant to keep behaviour (a refactor) can be checked to leave
# every output byte-identical:
#
#     bash tools/same_outputs.sh before.txt       # on the old commit
#     bash tools/same_outputs.sh after.txt        # on the new one
#     diff before.txt after.txt                   # no output: the same bytes
#
# With WETBOUNCE=path/to/binary it runs that binary instead (e.g. a copy of the old build), and
# with THREADS=T it runs each scene on T worker threads (default: all cores), so that lists made
# at 1, 2 and 16 threads show the results do not depend on the thread count.
#
# summary.json carries the run's wall time, which differs between runs: it is checked with that
# one field removed. Takes about 5 minutes on 2 cores (the column and the contactor dominate);
# about 18 with THREADS=1 and 10 with THREADS=16, where the dense bed and the heaps dominate.
set -euo pipefail
cd "$(dirname "$0")/.."
list=${1:?usage: bash tools/same_outputs.sh LIST_FILE [SCENE...]}
shift
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(scenes/*.toml)
# WETBOUNCE=path runs that binary instead of building this checkout's (a saved copy of the old one).
bin=${WETBOUNCE:-}
if [ -z "$bin" ]; then
  cargo build --release --quiet --bin wetbounce
  bin=target/release/wetbounce
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
: >"$list"
for scene in "${scenes[@]}"; do
  stem=$(basename "$scene" .toml)
  "$bin" run "$scene" --out "$out/$stem" --formats mcap,csv --quiet ${THREADS:+--threads "$THREADS"} >/dev/null
  for f in "$out/$stem"/*; do
    name="$stem/$(basename "$f")"
    if [ "$(basename "$f")" = summary.json ]; then
      sum=$(grep -v '"wall_time_s"' "$f" | sha256sum | cut -d' ' -f1)
    else
      sum=$(sha256sum "$f" | cut -d' ' -f1)
    fi
    echo "$sum  $name" >>"$list"
  done
  echo "$scene: done ($SECONDS s)" >&2
done
cat "$list"
