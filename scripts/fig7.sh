#!/usr/bin/env bash
# Reproduce the paper's Fig. 7 sweep (and the Sec. 3 grid comparison) on the
# default scenario. Usage: scripts/fig7.sh [OUT_DIR] [extra experiment flags]
set -euo pipefail
out=${1:-fig7-out}
shift || true
cargo build --release --bin gridswarm
./target/release/gridswarm experiment --out "$out" "$@"
./target/release/gridswarm experiment --grids --out "$out"
