#!/usr/bin/env bash
# The contactor's drops tracked by wetbounce and by OpenFOAM v1912's Lagrangian tracker in the
# same water flow, and both codes' run times.
#
#   apt-get install -y openfoam python3-numpy    # Debian: OpenFOAM v1912
#   bash tools/contactor_side_by_side.sh         # 14 min on this project's 2-core machine, under load
#
# 1. wetbounce runs scenes/contactor.toml (1500 toluene drops, L06's rule, drops held on the
#    baffles) with the `fluid_acceleration` effect added, on 1 thread, through
#    tools/contactor_drops.rs, which writes each drop's birth (time, diameter, position) and its
#    residence time at the outlet (z = 0.40 m).
# 2. peers/openfoam/contactor/mkcase.py builds an uncoupledKinematicParcelFoam case of the same
#    drops: the column as tools/cfd/make_blockmesh.py's 5-degree wedge (CELL = 0.5 mm cells, top
#    at z = 0.40), the water's velocity interpolated at the cell centres from the table the
#    engine reads (scenes/fields/contactor_rz.vti), one manualInjection per drop at its birth
#    time, diameter and (r, 0, z), Schiller–Naumann drag, gravity + buoyancy, added mass and
#    fluid acceleration (virtualMass 0.5 + pressureGradient), and walls with constant
#    restitution (standardWallInteraction rebound, E = 0.91, the scene's restitution_max). It
#    runs on 1 rank; patchPostProcessing records each drop's age when it reaches the top.
# 3. Prints both residence-time distributions (drops, reached, mean, p10, p50, p90, max) and
#    both run times (wall and CPU seconds of the run itself; OpenFOAM's case preparation apart).
#
# Knobs: CELL (0.0005 m), E (0.91), END (14 s, the scene's duration), WORK (a new temporary
#   directory, kept: it holds the drop list, both results and OpenFOAM's case and log tail).
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
MK=$HERE/peers/openfoam/contactor/mkcase.py
CELL=${CELL:-0.0005}; E=${E:-0.91}; END=${END:-14}
WORK=${WORK:-$(mktemp -d)}; mkdir -p "$WORK"
if ! command -v uncoupledKinematicParcelFoam >/dev/null; then
  for rc in /usr/lib/openfoam/openfoam*/etc/bashrc /opt/openfoam*/etc/bashrc; do
    # shellcheck disable=SC1090
    [ -f "$rc" ] && { set +u; . "$rc" >/dev/null 2>&1 || true; set -u; break; }
  done
fi
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
  export WM_PROJECT_DIR=/usr/share/openfoam   # all Debian's OpenFOAM needs to find its etc/
fi
for c in blockMesh postProcess uncoupledKinematicParcelFoam python3 /usr/bin/time; do
  command -v "$c" >/dev/null || { echo "$c not found: apt-get install -y openfoam python3-numpy" >&2; exit 1; }
done
python3 -c 'import numpy' 2>/dev/null || { echo "numpy not found: apt-get install -y python3-numpy" >&2; exit 1; }
cargo build --release --quiet --bin contactor_drops --manifest-path "$HERE/Cargo.toml"
BIN=${CARGO_TARGET_DIR:-$HERE/target}/release
echo "# work: $WORK"
# ------------------------------------------------------------------ wetbounce
# The shipped scene with fluid_acceleration (OpenFOAM's virtualMass and pressureGradient forces
# carry the water's acceleration: the same force on both sides), and the field's absolute path.
sed -e 's|^added_mass = {}|added_mass = {}\nfluid_acceleration = {}|' \
    -e "s|file = \"fields/contactor_rz.vti\"|file = \"$HERE/scenes/fields/contactor_rz.vti\"|" \
    "$HERE/scenes/contactor.toml" >"$WORK/contactor.toml"
grep -q '^fluid_acceleration' "$WORK/contactor.toml" || { echo "could not add fluid_acceleration to the scene" >&2; exit 1; }
/usr/bin/time -f "%e %U %S" -o "$WORK/wb.time" "$BIN/contactor_drops" "$WORK/contactor.toml" "$WORK/drops.csv" 1 >"$WORK/wb.log"
cat "$WORK/wb.log"
# ------------------------------------------------------------------ OpenFOAM
C=$WORK/of
rm -rf "$C"
T0=$(date +%s.%N)
python3 "$MK" mesh "$C" "$CELL" >"$WORK/of_prep.log"
blockMesh -case "$C" >>"$WORK/of_prep.log" 2>&1
postProcess -case "$C" -func writeCellCentres -time 0 >>"$WORK/of_prep.log" 2>&1
python3 "$MK" field "$C" "$HERE/scenes/fields/contactor_rz.vti" >>"$WORK/of_prep.log"
python3 "$MK" drops "$C" "$WORK/drops.csv" "$E" "$END" >>"$WORK/of_prep.log"
T1=$(date +%s.%N)
# The solver prints every injector's count every step (1500 x 3 lines, 2 GB in all): those
# lines are dropped, and of the rest only the end is kept.
/usr/bin/time -f "%e %U %S" -o "$WORK/of.time" uncoupledKinematicParcelFoam -case "$C" 2>&1 |
  grep -v -e '^    Injector drop' -e '^      - parcels added' -e '^      - mass introduced' | tail -n 2000 >"$WORK/of_run.log"
grep -q '^End' "$WORK/of_run.log" || { echo "OpenFOAM failed: $WORK/of_run.log" >&2; tail -n 40 "$WORK/of_run.log" >&2; exit 1; }
python3 "$MK" reached "$C" "$WORK/drops.csv" >"$WORK/of_residence.csv"
# ------------------------------------------------------------------ both
echo "# residence times (s) at z = 0.40: wetbounce L06 rule (drops held on baffles), OpenFOAM rebound e = $E"
python3 "$MK" compare "$WORK/drops.csv" "$WORK/of_residence.csv" "wetbounce (L06, 1 thread)" "OpenFOAM v1912 (e = $E, 1 rank)"
read -r WW WU WS <"$WORK/wb.time"; read -r OW OU OS <"$WORK/of.time"
WSTEP=$(sed -n 's/.*wall_s=\([0-9.]*\).*/\1/p' "$WORK/wb.log")
echo "# run times (s): wall and CPU (user+sys) of the whole process; wetbounce's stepping alone: $WSTEP s wall"
printf "%-34s %8s %8s\n" code wall_s cpu_s
printf "%-34s %8.1f %8.1f\n" "wetbounce (L06, 1 thread)" "$WW" "$(awk -v u="$WU" -v s="$WS" 'BEGIN{print u+s}')"
printf "%-34s %8.1f %8.1f   (+ %.1f s wall to build the case: mesh, field, 1500 injectors)\n" "OpenFOAM v1912 (e = $E, 1 rank)" "$OW" \
  "$(awk -v u="$OU" -v s="$OS" 'BEGIN{print u+s}')" "$(awk -v a="$T0" -v b="$T1" 'BEGIN{print b-a}')"
echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg)"
