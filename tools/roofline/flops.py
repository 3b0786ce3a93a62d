#!/usr/bin/env python3
"""Flops, instructions and memory traffic per particle-step of a run, counted (docs/roofline.md).

    python3 tools/roofline/flops.py PARTICLES STEPS -- [NAME=VALUE...] COMMAND... {steps}

runs COMMAND (with the NAME=VALUE settings in its environment) twice under callgrind, with `{steps}` replaced by STEPS and by 0, and prints the
difference per particle-step (STEPS × PARTICLES):

- instructions executed;
- flops: every executed instruction that does double-precision arithmetic (add, sub, mul,
  div, sqrt, and fused multiply-add as two), times its lanes (1 scalar, 2 xmm, 4 ymm, 8 zmm),
  found by matching callgrind's per-instruction counts to the disassembly of each object
  (objdump; the engine's own code and libm alike);
- bytes from memory: the last-level cache's misses (callgrind's cache simulation) times 64,
  reads and writes. The simulated last-level cache is the one Linux reports for this machine
  (/sys/devices/system/cpu/cpu0/cache/index3): callgrind's own detection read 384 MiB off the
  virtual machine's processor id here, against the 32 MiB lscpu shows.

The first step of a run (0 steps less nothing) is left out by the difference; what it costs
once (the scene built, the neighbour list's first build) is not a particle-step's.
"""
import collections
import os
import re
import subprocess
import sys
import tempfile

ARITH = re.compile(r"^v?(add|sub|mul|div|sqrt)(p|s)d$")
FMA = re.compile(r"^vf(n?m)(add|sub)(132|213|231)(p|s)d$")


def flops_of(mnemonic, operands):
    """Flops of one instruction (0 when it does no double arithmetic)."""
    lanes = 8 if "%zmm" in operands else 4 if "%ymm" in operands else 2
    m = ARITH.match(mnemonic)
    if m:
        return 1 if m.group(2) == "s" else lanes
    m = FMA.match(mnemonic)
    if m:
        return 2 if m.group(4) == "s" else 2 * lanes
    return 0


def disassembly(path):
    """{address: flops} of every instruction of the object, and {function name: address}."""
    out = subprocess.run(["objdump", "-d", "-C", "--no-show-raw-insn", path],
                         capture_output=True, text=True, check=True).stdout
    flops, symbols = {}, {}
    for line in out.splitlines():
        m = re.match(r"^([0-9a-f]+) <(.*)>:$", line)
        if m:
            symbols.setdefault(m.group(2), int(m.group(1), 16))
            continue
        m = re.match(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$", line)
        if m:
            f = flops_of(m.group(2), m.group(3))
            if f:
                flops[int(m.group(1), 16)] = f
    return flops, symbols


def strip_hash(name):
    return re.sub(r"::h[0-9a-f]{16}$", "", name)


def last_level_cache():
    """callgrind's --LL option for this machine's level-3 cache, or [] where Linux has none."""
    base = "/sys/devices/system/cpu/cpu0/cache/index3/"
    try:
        size = open(base + "size").read().strip()
        ways = open(base + "ways_of_associativity").read().strip()
        line = open(base + "coherency_line_size").read().strip()
    except OSError:
        return []
    scale = {"K": 1 << 10, "M": 1 << 20}.get(size[-1], 1)
    return [f"--LL={int(size.rstrip('KM')) * scale},{ways},{line}"]


def callgrind(command):
    """Totals of one run: instructions, flops, last-level misses (reads + writes)."""
    env = dict(os.environ)
    while command and re.match(r"^[A-Z_][A-Z0-9_]*=", command[0]):
        name, value = command.pop(0).split("=", 1)
        env[name] = value
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "cg.out")
        subprocess.run(["valgrind", "--tool=callgrind", "--dump-instr=yes", "--compress-pos=no",
                        "--compress-strings=no", "--cache-sim=yes", *last_level_cache(),
                        f"--callgrind-out-file={out}",
                        *command], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        events, npos, ob, fn = [], 1, None, None
        # Per object: {address: Ir}, and the first address seen in each function.
        counts = collections.defaultdict(collections.Counter)
        entries = collections.defaultdict(dict)
        misses = 0
        skip = False
        with open(out) as f:
            for line in f:
                if line.startswith("events:"):
                    events = line.split()[1:]
                elif line.startswith("positions:"):
                    npos = len(line.split()) - 1
                elif line.startswith("ob="):
                    ob = line[3:].strip()
                elif line.startswith("fn="):
                    fn = line[3:].strip()
                elif line.startswith(("cob=", "cfn=", "cfi=", "cfl=")):
                    pass
                elif line.startswith("calls="):
                    skip = True  # the next line is the call's inclusive cost
                elif line.startswith("0x"):
                    if skip:
                        skip = False
                        continue
                    parts = line.split()
                    addr = int(parts[0], 16)
                    # Positions (instr, and line with debug information), then the costs in
                    # the order of `events:`, trailing zeros left out.
                    cost = dict(zip(events, (int(v) for v in parts[npos:])))
                    counts[ob][addr] += cost.get("Ir", 0)
                    misses += cost.get("DLmr", 0) + cost.get("DLmw", 0)
                    e = entries[ob]
                    if fn not in e or addr < e[fn]:
                        e[fn] = addr
        instructions = sum(sum(c.values()) for c in counts.values())
        flops = 0
        for ob, c in counts.items():
            if not os.path.exists(ob):
                continue
            table, symbols = disassembly(ob)
            by_name = {strip_hash(k): v for k, v in symbols.items()}
            # The load offset: the most common (first address seen − symbol's address).
            offsets = collections.Counter(addr - by_name[strip_hash(f)]
                                          for f, addr in entries[ob].items() if strip_hash(f) in by_name)
            if not offsets:
                continue
            base = offsets.most_common(1)[0][0]
            if os.environ.get("FLOPS_DEBUG"):
                print(ob, offsets.most_common(3), file=sys.stderr)
            flops += sum(ir * table.get(addr - base, 0) for addr, ir in c.items())
        return instructions, flops, misses * 64


def main():
    if len(sys.argv) < 5 or "--" not in sys.argv:
        sys.exit(__doc__)
    i = sys.argv.index("--")
    particles, steps = int(sys.argv[1]), int(sys.argv[2])
    command = sys.argv[i + 1:]
    run = [callgrind([a.replace("{steps}", str(s)) for a in command]) for s in (steps, 0)]
    per = particles * steps
    ins, flops, dram = ((a - b) / per for a, b in zip(*run))
    print(f"instructions {ins:.1f}  flops {flops:.1f}  bytes_from_memory {dram:.1f}  "
          f"(per particle-step, {steps} steps less 0, {particles} particles)")


if __name__ == "__main__":
    main()
