#!/usr/bin/env bash
# What the README's two commands cost to build from a fresh clone (issue 26, item 5): clones
# this checkout's HEAD into a temporary folder, then times `cargo test --no-run` and
# `cargo build --release --bin wetbounce` (what `cargo run --release` builds) and prints the
# disk each leaves. Crates come from ~/.cargo (download time is not counted). Run it on a quiet
# machine: it uses every core for about 8 minutes on 2.
#
#     bash tools/build_cost.sh
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
dir=$(mktemp -d "${TMPDIR:-/tmp}/wetbounce-build-cost-XXXXXX")
trap 'rm -rf "$dir"' EXIT
git clone -q "$repo" "$dir/clone"
cd "$dir/clone"
unset CARGO_INCREMENTAL CARGO_TARGET_DIR
echo "commit $(git rev-parse --short HEAD)"
start=$SECONDS
cargo test --no-run --quiet
echo "cargo test --no-run: $((SECONDS - start)) s, $(du -sh target/debug | cut -f1) in target/debug"
start=$SECONDS
cargo build --release --quiet --bin wetbounce
echo "cargo build --release --bin wetbounce: $((SECONDS - start)) s, $(du -sh target/release | cut -f1) in target/release"
