#!/usr/bin/env bash
# Regenerates every plot and table of the accuracy study and the paper's figures from scratch:
# docs/accuracy/ (CSV, plots, tables; the README's table and docs/accuracy.md's tables are
# rewritten between their markers) and docs/figures/. Takes several minutes (the study).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release -p wetbounce-tools --bin paper_figures -- docs/figures "$@"
cargo run --release -p wetbounce-tools --bin restitution_emergent -- docs/figures "$@"
cargo run --release -p wetbounce-tools --bin bounce_comparison -- docs/figures "$@"
cargo run --release -p wetbounce-tools --bin accuracy_study -- docs/accuracy "$@"
