#!/usr/bin/env python3
"""How many of the history kernel's modes forget everything within one step (docs/performance.md,
"What naming `history` costs"): those with `lambda_k dt > 36`, whose decay over a step is below
1e-15.

    python3 tools/roofline/history_fast_modes.py [DT [WINDOW [TOLERANCE]]]   # 8.77e-6 1 1e-4

The rates are those of `ExponentialSum::inverse_sqrt` (src/correlations/history.rs) on
[1e-10 window, window], the same steps written again here: keep the two in step.
"""
import math
import sys


def rates(t_min, t_max, tol):
    h = math.pi**2 / (2 * math.log(2 * math.sqrt(2) / (0.7 * tol)))
    c = 2 / math.sqrt(math.pi)
    x_lo = math.log(1e-3 * tol * abs(math.expm1(-h)) / (h * c * math.sqrt(t_max)))
    x_hi = math.log(math.sqrt(math.log(1 / (0.3 * tol))) / math.sqrt(t_min))
    n = math.ceil((x_hi - x_lo) / h) + 1
    slow = min(10 * tol, 1e-3) / t_max
    kept = [math.exp(2 * (x_lo + k * h)) for k in range(n)]
    # The slow tail is lumped into one mode (its rate is not needed here).
    return [0.0] + [r for r in kept if r >= slow]


def main():
    args = [float(a) for a in sys.argv[1:]]
    dt, window, tol = (args + [8.77e-6, 1.0, 1e-4][len(args):])[:3]
    r = rates(1e-10 * window, window, tol)
    fast = sum(1 for x in r if x * dt > 36)
    print(f"dt {dt:g} s, window {window:g} s, tolerance {tol:g}: {len(r)} modes, {fast} with lambda dt > 36")


if __name__ == "__main__":
    main()
