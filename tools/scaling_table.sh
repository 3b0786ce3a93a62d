#!/bin/bash
# Thread scaling of tools/scaling.rs's cases on a many-core machine: 1, 2, 4, 8 and 16 threads
# at N = 1e5 (N5_STEPS steps, default 300) and at N = 1e6 (N6_STEPS, default 60), each case a
# process of its own that builds its scene once and times every thread count on it. The CSV goes
# to ${OUT:-.}/scaling16.csv and to standard output, the stage times to ${OUT:-.}/stderr.txt
# (docs/performance.md, "Thread scaling on a 16-core machine"). SCALING_BIN names the binary
# (default target/release/scaling: build it with `cargo build --release --bin scaling`, or carry
# a stripped copy to another machine); THREADS the counts (default 1,2,4,8,16; a count may come
# twice, `1,16,1,16`, to see the run-to-run spread), NS the particle counts (default
# "100000 1000000"), CSV the file's name.
set -u
B=${SCALING_BIN:-target/release/scaling}
out=${OUT:-.}
threads=${THREADS:-1,2,4,8,16}
csv=$out/${CSV:-scaling16.csv}
cases="dilute paper paper-lubrication paper-history pairs5 pairs5-friction poiseuille field field-vtu"
echo "case,n,threads,steps,wall_s,particle_steps_per_s" > "$csv"
for n in ${NS:-100000 1000000}; do
  if [ "$n" = 100000 ]; then steps=${N5_STEPS:-300}; else steps=${N6_STEPS:-60}; fi
  for case in $cases; do
    SCALING_N=$n SCALING_THREADS=$threads SCALING_STEPS=$steps timeout 300 "$B" - "$n" "$case" \
      2>>"$out/stderr.txt" | tail -n +2 >> "$csv"
  done
done
cat "$csv"
