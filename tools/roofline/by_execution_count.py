#!/usr/bin/env python3
"""Where one function's instructions go, by how often each instruction runs (docs/performance.md,
"What naming `history` costs").

    valgrind --tool=callgrind --dump-instr=yes --callgrind-out-file=cg.out \
        target/release/step_rate scenes/bench_paper_history.toml 200 1
    python3 tools/roofline/by_execution_count.py cg.out remembering_free_chunk_avx2 2000000

Sums callgrind's self cost per instruction address of the functions whose name contains the
given text, divides each by the particle-steps (here 200 steps x 10,000 beads), and prints, for
each execution count per particle-step (1.00: once per bead, 0.25: once per lane group of four),
how many distinct instructions run that often and what they add per particle-step.
"""
import collections
import re
import sys


def costs_by_address(path, name):
    """Self cost per instruction address of the functions whose name contains `name`."""
    costs = collections.Counter()
    names, current, last, after_call = {}, "", 0, False
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("fn="):
            m = re.match(r"fn=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(2):
                    names[m.group(1)] = m.group(2)
                current = names.get(m.group(1), "")
            else:
                current = line[3:]
            continue
        if line.startswith("cfn="):
            # A name may be given first where the function is called (name compression).
            m = re.match(r"cfn=\((\d+)\) (.*)", line)
            if m:
                names[m.group(1)] = m.group(2)
            continue
        if line.startswith("calls="):
            after_call = True  # the next cost line is the call's inclusive cost
            continue
        if not line or line[0] not in "0123456789+-*":
            continue
        parts = line.split()
        a = parts[0]
        if a.startswith("0x"):
            last = int(a, 16)
        elif a[0] in "+-":
            last += int(a)
        elif a != "*":
            last = int(a)
        if after_call:
            after_call = False
            continue
        if name in current and len(parts) > 1:
            costs[last] += int(parts[-1])
    return costs


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    path, name, particle_steps = sys.argv[1], sys.argv[2], float(sys.argv[3])
    costs = costs_by_address(path, name)
    buckets = collections.defaultdict(lambda: [0, 0.0])
    for cost in costs.values():
        per = cost / particle_steps
        if per > 0:
            b = buckets[round(per, 2)]
            b[0] += 1
            b[1] += per
    total = sum(costs.values()) / particle_steps
    print(f"{name}: {total:.1f} instructions per particle-step")
    print("runs per particle-step, distinct instructions, instructions per particle-step")
    for per, (count, added) in sorted(buckets.items(), reverse=True):
        if added >= 0.5:
            print(f"{per:8.2f} {count:6d} {added:8.1f}")


if __name__ == "__main__":
    main()
