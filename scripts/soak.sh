#!/usr/bin/env bash
# Soak the robots' protocol: the deterministic simulation test
# (shared/tests/vopr.rs) at greater length and with a fresh seed.
#
#   scripts/soak.sh [RUNS] [SEED]      # default 2,000,000 runs, a random seed
#
# Every failing case is printed with the `gridswarm simulate` command that
# replays it exactly; the same RUNS and SEED repeat the whole soak.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-2000000}
seed=${2:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}
echo "soak: $runs runs, seed $seed"
VOPR_RUNS=$runs VOPR_SEED=$seed cargo test --release --workspace --test vopr -- --nocapture faulty_runs
