#!/usr/bin/env bash
# Strong and weak scaling of one run over MPI ranks (docs/distributed.md, "Scaling"): the
# peer's dilute scene (scenes/bench_dilute.toml: glass beads at 3 d spacing in a viscous liquid,
# gravity, buoyancy and Stokes drag) grown to N beads and cut to STEPS steps, run as
#   1 rank × T threads and R ranks × 1 thread, for each R in RANKS,
# and, with L06's physics (scenes/bench_paper.toml's effects), the same. Prints one CSV line per
# run: case, beads, ranks, threads, steps, wall seconds, particle-steps per second. The rate is
# the run's own (summary.json's wall time: loading the scene and writing the two frames
# included).
#
#     bash tools/ranks_scaling.sh                       # N = 1e5, 1e6 beads; 1 and 2 ranks
#     RANKS="1 2 4 8 16" SIZES="1000000" bash tools/ranks_scaling.sh
#     WEAK=100000 RANKS="1 2" bash tools/ranks_scaling.sh   # 1e5 beads per rank
#
# Needs a build with `--features mpi` (WETBOUNCE=path, default target/release/wetbounce) and
# Open MPI's mpirun. Each rank is bound to no core (`--bind-to none`) so rayon's threads of a
# 1-rank run may use every core.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${WETBOUNCE:-target/release/wetbounce}
ranks=(${RANKS:-1 2})
sizes=(${SIZES:-100000 1000000})
steps=${STEPS:-200}
weak=${WEAK:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
root=()
[ "$(id -u)" = 0 ] && root=(--allow-run-as-root)
# A scene of about n beads: the dilute lattice (3 d spacing) in a box grown to hold them.
scene() {
  local n=$1 physics=$2 out=$3
  python3 - "$n" "$physics" "$steps" >"$out" <<'PY'
import sys, math
n, physics, steps = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
d, s = 2.5e-3, 7.5e-3
side = max(2, round(n ** (1 / 3)))
layers = max(1, round(n / side**2))
dt = 8.77e-6
effects = {
    "dilute": 'gravity = {}\nbuoyancy = {}\ndrag = { law = "stokes" }',
    "l06": 'gravity = {}\nbuoyancy = {}\ndrag = {}\nadded_mass = {}',
}[physics]
w, h = side * s, layers * s
print(f"""[simulation]
dt = {dt}
duration = {steps * dt}
output_interval = {steps * dt}
integrator = "euler"
[fluid]
density = 1000.0
viscosity = 0.1
gravity = [0.0, 0.0, -9.81]
[effects]
{effects}
[[kinds]]
name = "glass"
type = "solid"
density = 2540.0
youngs_modulus = 6e7
poisson_ratio = 0.23
restitution_max = 0.9
[[walls]]
name = "box"
type = "box"
min = [0.0, 0.0, 0.0]
max = [{w}, {w}, {h + 0.03}]
inside = true
[[lattice]]
kind = "glass"
diameter = {d}
min = [0.0, 0.0, 0.015]
max = [{w}, {w}, {0.015 + h}]
spacing = {s}
""")
PY
}
run() {
  local case=$1 n=$2 r=$3 t=$4 file=$5
  local out="$tmp/out-$r-$t"
  rm -rf "$out"
  if [ "$r" = 1 ]; then
    "$bin" run "$file" --out "$out" --formats csv --quiet --threads "$t" --allow-large-output >/dev/null
  else
    mpirun "${root[@]}" --oversubscribe --bind-to none -np "$r" "$bin" run "$file" --out "$out" \
      --formats csv --quiet --threads "$t" --allow-large-output >/dev/null
  fi
  python3 - "$out/summary.json" "$case" "$n" "$r" "$t" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
n = s["particles"]["alive"]
steps, wall = s["steps"], s["wall_time_s"]
case, _, r, t = sys.argv[2:6]
print(f"{case},{n},{r},{t},{steps},{wall:.3f},{n * steps / wall:.4g}")
PY
}
echo "case,beads,ranks,threads,steps,wall_s,particle_steps_per_s"
for physics in dilute l06; do
  if [ -n "$weak" ]; then
    for r in "${ranks[@]}"; do
      n=$((weak * r)); scene "$n" "$physics" "$tmp/s.toml"
      run "$physics-weak" "$n" "$r" 1 "$tmp/s.toml"
    done
    continue
  fi
  for n in "${sizes[@]}"; do
    scene "$n" "$physics" "$tmp/s.toml"
    for r in "${ranks[@]}"; do
      run "$physics" "$n" 1 "$r" "$tmp/s.toml"
      [ "$r" = 1 ] || run "$physics" "$n" "$r" 1 "$tmp/s.toml"
    done
  done
done
