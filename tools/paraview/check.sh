#!/usr/bin/env bash
# Opens a shipped scene's ParaView output with the real ParaView, checks the numbers it reads
# back against trajectories.csv, and renders a frame offscreen to
# out/paraview/<scene>/paraview_<scene>.png.
#
#     bash tools/paraview/check.sh [SCENE [TIME]]     # default: settling_bed, its last frame
#
#     WETBOUNCE_BIN=target/release/wetbounce   use this binary (default: build it in release)
#     PNG=docs/figures/paraview_<scene>.png    where the picture goes (this one redraws the
#                                              one in docs/output.md)
#
# Needs ParaView's pvbatch with its Python modules, and an X server to render into: Debian's
# `paraview` is built for X only (pvbatch --force-offscreen-rendering aborts: no EGL or OSMesa),
# so the script runs it in a virtual one (xvfb-run) when DISPLAY is unset. On Debian or Ubuntu, as root,
# it installs what is missing itself: paraview, python3-paraview, xvfb (about 220 MB to download,
# 1.3 GB on disk). CI does not run this: tests/output/output_vtk.rs checks the files with vtkio.
set -euo pipefail
cd "$(dirname "$0")/../.."

scene=${1:-settling_bed}
time_arg=${2:-}
out=out/paraview/$scene
png=${PNG:-$out/paraview_$scene.png}

missing=()
command -v pvbatch > /dev/null || missing+=(paraview)
[ -d /usr/lib/python3/dist-packages/paraview ] || command -v pvpython > /dev/null || missing+=(python3-paraview)
[ -n "${DISPLAY:-}" ] || command -v xvfb-run > /dev/null || missing+=(xvfb)
if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get > /dev/null; then
        echo "installing ${missing[*]}"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
    else
        echo "missing: ${missing[*]} (Debian/Ubuntu packages; install them as root)" >&2
        exit 1
    fi
fi

if [ -n "${WETBOUNCE_BIN:-}" ]; then
    bin=$WETBOUNCE_BIN
    [ -x "$bin" ] || { echo "WETBOUNCE_BIN=$bin: not an executable file" >&2; exit 1; }
else
    cargo build --release --locked --bin wetbounce
    bin=target/release/wetbounce
fi
# The output folder is made anew; the picture (inside it by default) is rendered after the run.
rm -rf "$out"
mkdir -p "$(dirname "$png")"
"$bin" run "scenes/$scene.toml" --formats vtk,csv --quiet --out "$out"
du -sh "$out"/"$scene"_vtk "$out/$scene.pvd" "$out/${scene}_walls.vtp" "$out/trajectories.csv" | sed 's/^/size /'

if [ -n "${DISPLAY:-}" ]; then
    pvbatch tools/paraview/render.py "$out" "$scene" "$png" $time_arg
else
    # A virtual X server on a free display number (-a), 24-bit colour, larger than the picture:
    # a window that does not fit the screen fails with "bad X server connection".
    xvfb-run -a -s "-screen 0 1600x1200x24 -nolisten tcp" \
        pvbatch tools/paraview/render.py "$out" "$scene" "$png" $time_arg
fi
