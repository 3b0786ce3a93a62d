#!/usr/bin/env bash
# Builds what a user installs without a Rust toolchain (issue 30, item 1), into DIR (default
# dist/):
#
# - wetbounce-VERSION-TARGET.tar.gz: the stripped command-line program with the shipped scenes,
#   the docs, the README, the licences, the citation and the changelog. It is built with the
#   `rerun` feature, so that it also writes rerun's native recording (particles at their radii,
#   walls, events; docs/output.md) without the user building rerun: 9 minutes more to build on
#   the 2-core machine, a stripped program of 27 MB and an archive of 10.4 MB (8.1 without);
# - wetbounce-VERSION-cp311-abi3-PLATFORM.whl: the Python module, one wheel for every CPython
#   >= 3.11 (abi3), built by maturin (`pip install maturin`) and stripped.
#
#     bash tools/dist.sh [DIR]
#
# Both come from the release profile. DIST_PROFILE=dev builds them unoptimised instead, which
# only CI does: it checks the packaging in minutes, reusing its dev build, where two cold release
# builds took 27 of its 90 minutes (slow programs, never for users). Install the wheel with
# `pip install DIR/wetbounce-*.whl`; unpack the archive anywhere and run
# `./wetbounce run scenes/toluene_drop.toml`.
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mkdir -p "${1:-dist}" && cd "${1:-dist}" && pwd)
version=$(sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
target=$(rustc -vV | sed -n 's/^host: //p')
name="wetbounce-$version-$target"
profile=${DIST_PROFILE:-release}
case $profile in
  release) built=release ;;
  dev) built=debug ;;
  *) echo "tools/dist.sh: DIST_PROFILE=$profile: not release or dev" >&2; exit 2 ;;
esac
cargo build --profile "$profile" --quiet --bin wetbounce --features rerun
stage=$(mktemp -d "${TMPDIR:-/tmp}/wetbounce-dist-XXXXXX")
trap 'rm -rf "$stage"' EXIT
mkdir "$stage/$name"
cp "${CARGO_TARGET_DIR:-target}/$built/wetbounce" "$stage/$name/"
strip "$stage/$name/wetbounce"
cp -r scenes docs README.md LICENSE-MIT LICENSE-APACHE CITATION.cff CHANGELOG.md "$stage/$name/"
tar -czf "$out/$name.tar.gz" -C "$stage" "$name"
(cd python && maturin build --profile "$profile" --strip --quiet --out "$out")
ls -l "$out"
