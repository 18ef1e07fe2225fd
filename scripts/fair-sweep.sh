#!/usr/bin/env bash
# The Fig. 7 sweep at each of several base seeds, and the three claims'
# verdicts at each: at the search's end (search_time_s) and at the last
# find (last_target_s). docs/paper.md's reproduction section comes from it.
# Usage: scripts/fair-sweep.sh [OUT_DIR] [SEEDS] [extra experiment flags]
# (SEEDS comma-separated; default the issue-36 review's five and the default 1).
set -euo pipefail
out=${1:-fair-sweep-out}
seeds=${2:-1,11,23,37,51,73}
shift 2 || shift $# || true
bin=${GRIDSWARM:-./target/release/gridswarm}
[ -n "${GRIDSWARM:-}" ] || cargo build --release --bin gridswarm
mkdir -p "$out"
for s in ${seeds//,/ }; do
  "$bin" experiment --seed "$s" --out "$out/seed-$s" "$@" >"$out/seed-$s.txt"
  tail -n 1 "$out/seed-$s.txt" >&2
done
python3 - "$out" "$seeds" <<'PY'
import json, sys
out, seeds = sys.argv[1], sys.argv[2].split(",")
letter = {"holds": "H", "fails": "F", "undecided": "U", "not_evaluated": "-"}
rows = {}
for s in seeds:
    with open(f"{out}/seed-{s}/summary.json") as f:
        d = json.load(f)
    for key in ("claims", "claims_at_last_find"):
        for c in d.get(key, []):
            rows.setdefault((key, c["id"]), []).append(letter[c["verdict"]])
print(f"seeds {','.join(seeds)}: H holds, F does not hold, U not decidable at this sample size")
print(f"{'measure':<28}{'claim':<7}verdicts")
for (key, cid), v in sorted(rows.items()):
    measure = "search end (search_time_s)" if key == "claims" else "last find (last_target_s)"
    print(f"{measure:<28}({cid})    {''.join(v)}")
PY
