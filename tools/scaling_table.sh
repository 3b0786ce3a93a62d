#!/bin/bash
# Thread scaling of tools/scaling.rs's cases: 1-16 threads at N = 1e5 (100 steps) and 1 and 16
# threads at N = 1e6 (30 steps), each run a process of its own; the CSV goes to
# ${OUT:-.}/scaling16.csv and to standard output (docs/performance.md, "Thread scaling on a
# 16-core machine"). SCALING_BIN names the binary (default target/release/scaling: build it with
# `cargo build --release --bin scaling`, or carry a stripped copy to another machine).
set -u
B=${SCALING_BIN:-target/release/scaling}
out=${OUT:-.}
csv=$out/scaling16.csv
echo "case,n,threads,steps,wall_s,particle_steps_per_s" > "$csv"
for case in dilute paper paper-lubrication paper-history pairs5 pairs5-friction poiseuille field field-vtu; do
  for t in 1 2 4 8 16; do
    SCALING_N=100000 SCALING_THREADS=$t SCALING_STEPS=100 timeout 90 "$B" - 100000 "$case" \
      2>>"$out/stderr.txt" | tail -n +2 >> "$csv"
  done
done
for case in dilute paper pairs5 pairs5-friction; do
  for t in 1 16; do
    SCALING_N=1000000 SCALING_THREADS=$t SCALING_STEPS=30 timeout 120 "$B" - 1000000 "$case" \
      2>>"$out/stderr.txt" | tail -n +2 >> "$csv"
  done
done
cat "$csv"
