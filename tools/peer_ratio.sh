#!/usr/bin/env bash
# Runs the LIGGGHTS peer (peers/liggghts/in.s1_dilute) and wetbounce on the same
# dilute scene (scenes/bench_dilute.toml: same spheres, box, fluid, effects and step count),
# one after the other in one run, with 1 and 2 ranks/threads, and prints the ratio; then
# wetbounce with L06's heavier physics on the same beads (scenes/bench_paper.toml:
# Schiller–Naumann drag, added mass, RK2), the same with wall lubrication, with the history
# force, and with everything (scenes/bench_paper_full.toml: lubrication, history, rotation
# and friction) against the peer's dilute rates of this run. Last, the dense bed: the peer's
# in.s2_bed (10,000 beads settled by in.s2_bed_prep, then stepped with friction) against
# scenes/bench_bed_friction.toml's beads, settled by a run of that scene with a longer step
# (checkpointed at its end) and stepped from there (`step_rate … --from`), both at 1 and 2
# ranks/threads. The settling runs are not timed.
#
#   apt-get install -y liggghts          # Debian package, with Open MPI
#   bash tools/peer_ratio.sh             # STEPS=20000, BED_STEPS=2000 by default
#   BED_STEPS=0 bash tools/peer_ratio.sh # without the dense bed (its settling takes ~25 min)
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
PEERS=${PEERS:-$HERE/peers/liggghts}
STEPS=${STEPS:-20000}
# The dense bed's steps, for both engines: its rate is steady, and 20,000 steps of wetbounce's
# lasting-contact solve over a settled bed take minutes.
BED_STEPS=${BED_STEPS:-2000}
command -v liggghts >/dev/null || { echo "liggghts not found: apt-get install -y liggghts" >&2; exit 1; }
cargo build --release --quiet --bin step_rate --bin wetbounce --manifest-path "$HERE/Cargo.toml"
BIN=${CARGO_TARGET_DIR:-$HERE/target}/release
WORK=$(mktemp -d)
cp "$PEERS"/common_params.liggghts "$PEERS"/in.s1_dilute "$PEERS"/in.s2_bed_prep "$PEERS"/in.s2_bed "$WORK"/
cd "$WORK"
N=10000
lig() { # ranks [input [steps]]
  local steps=${3:-$STEPS}
  local cmd=(liggghts -in "${2:-in.s1_dilute}" -var nsteps "$steps" -var out 0 -log log.$1 -screen none)
  if [ "$1" -gt 1 ]; then cmd=(mpirun --allow-run-as-root -np "$1" "${cmd[@]}"); fi
  "${cmd[@]}" >/dev/null 2>&1
  awk -v n=$N -v s="$steps" '/^Loop time of/{t=$4} END{printf "%.4e", n*s/t}' log.$1
}
wb() { # threads [scene [steps [step_rate options]]]
  "$BIN/step_rate" "$HERE/scenes/${2:-bench_dilute}.toml" "${3:-$STEPS}" "$1" "${@:4}" | awk -F'particle_steps_per_s=' '/particle_steps_per_s/{print $2}'
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
# The dense bed: each engine settles its beads first (not timed), then steps the bed.
# (with a screen: LIGGGHTS 3.8.0's insert/pack segfaults writing to none, peers/liggghts/run.sh)
if [ "$BED_STEPS" -gt 0 ]; then
  liggghts -in in.s2_bed_prep -log log.prep >screen.prep 2>&1
  sed -e 's/^dt = 8.77e-6/dt = 2e-4/' -e 's/^duration = 0.1754 .*/duration = 3.0/' \
    -e 's/^output_interval = 0.1754/output_interval = 3.0/' "$HERE/scenes/bench_bed_friction.toml" >settle.toml
  "$BIN/wetbounce" run settle.toml --out settled --formats csv --quiet --checkpoint-every 3.0 >/dev/null
  CHECKPOINT=$(ls settled/checkpoints/checkpoint-*.wbck | tail -1)
  for r in 1 2; do
    L=$(lig $r in.s2_bed "$BED_STEPS"); W=$(wb $r bench_bed_friction "$BED_STEPS" --from "$CHECKPOINT")
    printf "%-18s %-8s %16s %16s %8.2f\n" S2_bed "$r" "$L" "$W" "$(awk -v w="$W" -v l="$L" 'BEGIN{print w/l}')"
  done
fi
rm -rf "$WORK"
