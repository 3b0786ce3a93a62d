#!/usr/bin/env bash
# What drawing the particles as spheres costs in the MCAP (issue 30, item 3): runs a settling
# bed of N glass beads (settling_bed's beads and water, a box scaled to 10 % solids) with the
# spheres on /scene (the default) and without them (--max-spheres 0), and prints the MCAP's
# bytes per particle per frame both ways.
#
#     bash tools/foxglove/size.sh [N ...]        # default: 10000 100000
#
# It uses target/release/wetbounce (built if missing) or WETBOUNCE_BIN, and writes into
# out/foxglove_size/ (OUT= to change). The files it leaves are the ones
# tools/foxglove/load.mjs opens.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin=${WETBOUNCE_BIN:-target/release/wetbounce}
[ -n "${WETBOUNCE_BIN:-}" ] || cargo build --release --quiet --bin wetbounce
out=${OUT:-out/foxglove_size}
mkdir -p "$out"
frames=11
printf "%8s %7s %22s %22s %8s\n" particles frames "MCAP with spheres" "MCAP without" "ratio"
[ $# -gt 0 ] || set -- 10000 100000
for n in "$@"; do
  # A cube holding n beads of 2.5 mm at 10 % solids: side = (n · π d³/6 / 0.1)^(1/3).
  side=$(python3 -c "import math; print(f'{(int($n) * math.pi * 2.5e-3**3 / 6 / 0.1) ** (1 / 3):.4f}')")
  scene="$out/bed_$n.toml"
  sed -e "s/^duration = .*/duration = 0.2/" -e "s/^output_interval = .*/output_interval = 0.02/" \
    -e "s/^max = \[0.04, 0.04, 0.2\]/max = [$side, $side, $(python3 -c "print(2 * $side)")]/" \
    -e "s/^max = \[0.04, 0.04, 0.15\]/max = [$side, $side, $(python3 -c "print(0.02 + $side)")]/" \
    -e "s/^count = .*/count = $n/" scenes/settling_bed.toml >"$scene"
  "$bin" run "$scene" --formats mcap --quiet --out "$out/spheres_$n" >/dev/null
  "$bin" run "$scene" --formats mcap --quiet --out "$out/points_$n" --max-spheres 0 >/dev/null
  with=$(stat -c %s "$out/spheres_$n/bed_$n.mcap")
  without=$(stat -c %s "$out/points_$n/bed_$n.mcap")
  per() { python3 -c "print(f'{$1 / 1e6:.1f} MB, {$1 / ($n * $frames):.1f} B/pf')"; }
  printf "%8s %7s %22s %22s %8s\n" "$n" "$frames" "$(per "$with")" "$(per "$without")" \
    "$(python3 -c "print(f'{$with / $without:.2f}')")"
done
