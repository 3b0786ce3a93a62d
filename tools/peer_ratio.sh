#!/usr/bin/env bash
# Runs the LIGGGHTS peer (peers/liggghts/in.s1_dilute) and wetbounce on the same
# dilute scene (scenes/bench_dilute.toml: same spheres, box, fluid, effects and step count),
# one after the other in one run, with 1 and 2 ranks/threads, and prints the ratio; then
# wetbounce with L06's heavier physics on the same beads (scenes/bench_paper.toml:
# Schiller–Naumann drag, added mass, RK2), the same with wall lubrication, with the history
# force, and with everything (scenes/bench_paper_full.toml: lubrication, history, rotation
# and friction) against the peer's dilute rates of this run.
#
#   apt-get install -y liggghts          # Debian package, with Open MPI
#   bash tools/peer_ratio.sh             # STEPS=20000 by default
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
PEERS=${PEERS:-$HERE/peers/liggghts}
STEPS=${STEPS:-20000}
command -v liggghts >/dev/null || { echo "liggghts not found: apt-get install -y liggghts" >&2; exit 1; }
cargo build --release --quiet --bin step_rate --manifest-path "$HERE/Cargo.toml"
WORK=$(mktemp -d)
cp "$PEERS"/common_params.liggghts "$PEERS"/in.s1_dilute "$WORK"/
cd "$WORK"
N=10000
lig() { # ranks
  local cmd=(liggghts -in in.s1_dilute -var nsteps "$STEPS" -var out 0 -log log.$1 -screen none)
  if [ "$1" -gt 1 ]; then cmd=(mpirun --allow-run-as-root -np "$1" "${cmd[@]}"); fi
  "${cmd[@]}" >/dev/null 2>&1
  awk -v n=$N -v s="$STEPS" '/^Loop time of/{t=$4} END{printf "%.4e", n*s/t}' log.$1
}
wb() { # threads [scene]
  "${CARGO_TARGET_DIR:-$HERE/target}/release/step_rate" "$HERE/scenes/${2:-bench_dilute}.toml" "$STEPS" "$1" | awk -F'particle_steps_per_s=' '/particle_steps_per_s/{print $2}'
}
printf "%-18s %-8s %16s %16s %8s\n" scene ranks liggghts_psps wetbounce_psps ratio
declare -A PEER
for r in 1 2; do
  L=$(lig $r); W=$(wb $r); PEER[$r]=$L
  printf "%-18s %-8s %16s %16s %8.2f\n" S1_dilute "$r" "$L" "$W" "$(awk -v w="$W" -v l="$L" 'BEGIN{print w/l}')"
done
for scene in bench_paper bench_paper_lubrication bench_paper_history bench_paper_full; do
  for r in 1 2; do
    L=${PEER[$r]}; W=$(wb $r $scene)
    printf "%-18s %-8s %16s %16s %8.2f\n" "${scene#bench_}" "$r" "$L" "$W" "$(awk -v w="$W" -v l="$L" 'BEGIN{print w/l}')"
  done
done
rm -rf "$WORK"
