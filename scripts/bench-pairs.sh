#!/usr/bin/env bash
# Two builds of gridswarm measured in interleaved pairs (BENCHMARKS.md):
# the default Fig. 7 sweep's user CPU, wall time and robot-rounds, then the
# distributed round's p50 at 13 robots (paper, seeds 1-3) and 200 (large,
# 30 rounds, seeds 1-2). Each build's folder must hold its world-server and
# robot-agent beside gridswarm.
# Usage: scripts/bench-pairs.sh OLD_GRIDSWARM NEW_GRIDSWARM [PAIRS]
set -euo pipefail
old=$1 new=$2 pairs=${3:-3}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/gridswarm-bench-XXXXXX")
trap 'rm -rf "$tmp"' EXIT
rounds() { python3 -c "import csv,sys; print(sum(int(r['rounds'])*int(r['robots']) for r in csv.DictReader(open(sys.argv[1]))))" "$1"; }
p50() { python3 -c "import json,sys; d=json.load(sys.stdin); print(round(d['round_wall_ms']['p50'],3), d['rounds'])"; }
for i in $(seq "$pairs"); do
  for b in old new; do
    bin=$old; [ $b = new ] && bin=$new
    /usr/bin/time -f "%U %e" -o "$tmp/time" "$bin" experiment --out "$tmp/$b-$i" >/dev/null 2>&1
    echo "fig7 pair $i $b user_s,wall_s $(cat "$tmp/time") robot_rounds $(rounds "$tmp/$b-$i/runs.csv")"
  done
done
for s in 1 2 3; do
  for b in old new; do
    bin=$old; [ $b = new ] && bin=$new
    echo "run 13 seed $s $b p50_ms,rounds $("$bin" run --robots 13 --seed "$s" --json 2>/dev/null | p50)"
  done
done
for s in 1 2; do
  for b in old new; do
    bin=$old; [ $b = new ] && bin=$new
    echo "run 200 seed $s $b p50_ms,rounds $("$bin" run --scenario large --robots 200 --max-rounds 30 --seed "$s" --json 2>/dev/null | p50)"
  done
done
