#!/usr/bin/env bash
# Runs the OpenFOAM v1912 peer (peers/openfoam: uncoupledKinematicParcelFoam tracking the 10,000
# glass beads of scenes/bench_paper.toml, Schiller–Naumann drag, added mass, exact-exponential
# integration) and wetbounce's step_rate on the same scene, interleaved in one run (each
# OpenFOAM run followed at once by step_rate with as many threads), with 1 and 2 ranks/threads,
# and prints the rates and the ratio wetbounce / OpenFOAM.
#
#   apt-get install -y openfoam openmpi-bin      # Debian package (v1912), with Open MPI
#   bash tools/peer_ratio_openfoam.sh            # STEPS=5000: 6.5 min on a busy 2-core machine
#
# OpenFOAM's rate is a difference of two runs of the same case, STEPS and NSHORT steps long, so
# start-up, mesh reading, injection and the final write cancel:
#   openfoam_gross = 10000 (STEPS - NSHORT) / (T_STEPS - T_NSHORT)
#   openfoam_net   = the same, less the same difference for the case with 0 parcels (the time
#                    loop and carrier fields, which cost OpenFOAM something with no parcel)
# The ratio is taken against openfoam_net, OpenFOAM's better figure. wetbounce's rate is
# step_rate's particle_steps_per_s on scenes/bench_paper.toml (WB_STEPS steps). On 1 rank the
# same rates from CPU time (user+sys, the same differences for OpenFOAM; step_rate's whole
# process for wetbounce) and their ratio_c are printed too: they change less than wall times
# when other processes share the cores (on 2 ranks, waiting ranks spin and burn CPU, so there
# is no such figure). Every OpenFOAM
# run and every step_rate run is timed once: peers/openfoam/run.sh is the careful version
# (physics check, repetitions, waits for an idle machine, re-runs of disturbed pairs).
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
PEER=$HERE/peers/openfoam
STEPS=${STEPS:-5000}; NSHORT=${NSHORT:-500}; WB_STEPS=${WB_STEPS:-20000}
SCENE=$HERE/scenes/bench_paper.toml
# Debian's OpenFOAM needs only WM_PROJECT_DIR to find its etc/ files (its bashrc complains
# about helper scripts the package does not ship); an upstream install has a bashrc to source.
if ! command -v uncoupledKinematicParcelFoam >/dev/null; then
  for rc in /usr/lib/openfoam/openfoam*/etc/bashrc /opt/openfoam*/etc/bashrc; do
    # shellcheck disable=SC1090
    [ -f "$rc" ] && { set +u; . "$rc" >/dev/null 2>&1 || true; set -u; break; }
  done
fi
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
  export WM_PROJECT_DIR=/usr/share/openfoam
fi
for c in blockMesh decomposePar uncoupledKinematicParcelFoam mpirun /usr/bin/time; do
  command -v "$c" >/dev/null || { echo "$c not found: apt-get install -y openfoam openmpi-bin" >&2; exit 1; }
done
cargo build --release --quiet --bin step_rate --manifest-path "$HERE/Cargo.toml"
STEP_RATE=${CARGO_TARGET_DIR:-$HERE/target}/release/step_rate
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
N=10000
mk() { # nparcels nsteps -> case dir
  local c=$WORK/np$1_n$2
  bash "$PEER/mkcase.sh" "$c" "$2" "$1" WenYuDrag analytical
  blockMesh -case "$c" >"$c/log.blockMesh" 2>&1
  decomposePar -case "$c" -force >"$c/log.decomposePar" 2>&1
  echo "$c"
}
of_time() { # case ranks -> "wall CPU" seconds of one run (CPU: user+sys of it and its children)
  local c=$1 r=$2 t0 t1
  rm -rf "$c"/0.* "$c"/processor*/0.*
  t0=$(date +%s.%N)
  if [ "$r" -eq 1 ]; then /usr/bin/time -f "%U %S" -o "$c/time" uncoupledKinematicParcelFoam -case "$c" >"$c/log.run" 2>&1
  else /usr/bin/time -f "%U %S" -o "$c/time" mpirun --allow-run-as-root -np "$r" uncoupledKinematicParcelFoam -case "$c" -parallel >"$c/log.run" 2>&1; fi
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" '{printf "%.3f %.2f\n", b-a, $1+$2}' "$c/time"
}
wb() { # threads -> "particle_steps_per_s CPU_seconds"
  /usr/bin/time -f "%U %S" -o "$WORK/wb.time" "$STEP_RATE" "$SCENE" "$WB_STEPS" "$1" >"$WORK/wb.log"
  awk -F'particle_steps_per_s=' '/particle_steps_per_s/{printf "%s ", $2+0}' "$WORK/wb.log"
  awk '{printf "%.2f\n", $1+$2}' "$WORK/wb.time"
}
CN=$(mk $N "$STEPS"); CS=$(mk $N "$NSHORT"); ZN=$(mk 0 "$STEPS"); ZS=$(mk 0 "$NSHORT")
echo "# bench_paper.toml: $N beads; OpenFOAM $STEPS - $NSHORT steps, wetbounce $WB_STEPS steps; $(nproc) cores"
printf "%-8s %16s %16s %16s %8s %12s %12s %8s %6s\n" ranks openfoam_gross openfoam_net wetbounce_psps ratio of_cpu_psps wb_cpu_psps ratio_c load1
for r in 1 2; do
  L1=$(cut -d' ' -f1 /proc/loadavg)
  read -r TN CN_ < <(of_time "$CN" "$r"); read -r W WC < <(wb "$r")
  read -r TS CS_ < <(of_time "$CS" "$r"); read -r T0N C0N < <(of_time "$ZN" "$r"); read -r T0S C0S < <(of_time "$ZS" "$r")
  awk -v r="$r" -v n=$N -v s="$STEPS" -v ns="$NSHORT" -v tn="$TN" -v ts="$TS" -v zn="$T0N" -v zs="$T0S" \
      -v cn="$CN_" -v cs="$CS_" -v c0n="$C0N" -v c0s="$C0S" -v w="$W" -v wc="$WC" -v ws="$WB_STEPS" -v l="$L1" 'BEGIN{
    g = n*(s-ns)/(tn-ts); net = n*(s-ns)/((tn-ts)-(zn-zs))
    if (r == 1) { oc = n*(s-ns)/((cn-cs)-(c0n-c0s)); wcr = n*ws/wc
      printf "%-8s %16.4e %16.4e %16.4e %8.2f %12.4e %12.4e %8.2f %6s\n", r, g, net, w, w/net, oc, wcr, wcr/oc, l }
    else printf "%-8s %16.4e %16.4e %16.4e %8.2f %12s %12s %8s %6s\n", r, g, net, w, w/net, "-", "-", "-", l }'
done
