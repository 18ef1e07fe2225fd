#!/usr/bin/env bash
# Regenerate robot-agent/hot-symbols.txt: the functions an iceoryx2 agent
# runs, which robot-agent/build.rs asks lld to place first so that they
# share few pages (see build.rs). Needs valgrind.
#
#   scripts/agent-hot-symbols.sh
#
# Robot 0 of three short runs (`large` with faults and loss, `paper` in
# situation 1) runs under callgrind; every function it entered that the
# binary defines is listed. Symbol names carry hashes of the build (features
# unified across the workspace, the profile, link flags, the lock file): the
# agent of `cargo build --release --workspace`, which `cargo test --release
# --workspace` reuses (tests/tests/features.rs); lld skips the names a
# binary lacks. Rerun it after a change of the lock file, of features or of
# the release profile (a stale list only loses memory, never correctness),
# then check an agent's RSS (BENCHMARKS.md, distributed).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$PWD/target/release/robot-agent
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat >"$tmp/agent" <<WRAP
#!/usr/bin/env bash
case "\$*" in
  *robot-0.json*) exec valgrind --tool=callgrind --demangle=no --dump-instr=no \
      --callgrind-out-file="$tmp/cg.\$\$" "$bin" "\$@" 2>/dev/null ;;
  *) exec "$bin" "\$@" ;;
esac
WRAP
chmod +x "$tmp/agent"
# A run stopped at --max-rounds exits 3 (incomplete): that is expected here.
gs() { ./target/release/gridswarm "$@" >/dev/null || [ $? -eq 3 ]; }

# Appends to $tmp/hot the functions of the current agent that robot 0 runs.
profile() {
    rm -f "$tmp"/cg.*
    gs run --scenario large --robots 13 --max-rounds 30 --agent-bin "$tmp/agent" --json
    gs run --scenario large --robots 60 --max-rounds 60 --kill 3@5 --loss 0.1 --retries 1 \
        --agent-bin "$tmp/agent" --json
    gs run --robots 13 --situation 1 --agent-bin "$tmp/agent" --json
    sed -n 's/^c\{0,1\}fn=([0-9]*) //p' "$tmp"/cg.* | sort -u >"$tmp/ran"
    nm -n --defined-only "$bin" | awk '$2 ~ /^[tTwW]$/ {print $3}' >"$tmp/defined"
    awk 'NR == FNR {ran[$0] = 1; next} ($0 in ran)' "$tmp/ran" "$tmp/defined" >>"$tmp/hot"
}

# With a list present: its link flags take part in the hashes.
touch robot-agent/hot-symbols.txt
: >"$tmp/hot"
cargo build --release --workspace
profile
awk '!seen[$0]++' "$tmp/hot" >robot-agent/hot-symbols.txt
cargo build --release --workspace
echo "robot-agent/hot-symbols.txt: $(wc -l <robot-agent/hot-symbols.txt) functions"
