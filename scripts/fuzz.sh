#!/usr/bin/env bash
# Fuzz the scenario parser and wire decoding (shared/tests/fuzz.rs) at
# greater length than `cargo test` does (256 cases per target).
#
#   scripts/fuzz.sh [CASES] [FILTER]   # default 100,000 cases per target, every target
#
# A failure prints its input on one line (the mutated scenario file as an
# escaped string, or the bytes in hex), and proptest records its seed in
# shared/proptest-regressions/fuzz.txt: the next run, `cargo test` included,
# replays it first. Commit that file with the fix.
set -euo pipefail
cd "$(dirname "$0")/.."
cases=${1:-100000}
filter=${2:-}
echo "fuzz: $cases cases per target${filter:+, only $filter}"
PROPTEST_CASES=$cases cargo test --release --workspace --test fuzz -- ${filter:+"$filter"}
