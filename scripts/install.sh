#!/usr/bin/env bash
# Installs the three programs, gridswarm, world-server and robot-agent, into
# one folder (by default cargo install's, ~/.cargo/bin): `gridswarm run`
# starts the other two from the folder it runs from (symlinks resolved;
# orchestrator/src/supervise/launch.rs), so they go together. `cargo install
# --path orchestrator` would install gridswarm alone, and building each
# package on its own would compile most of the workspace three times over.
#
#   scripts/install.sh [DIR]
#
# Builds first with the README's `cargo build --release` (nothing is
# compiled again after that build), then copies the binaries.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-${CARGO_INSTALL_ROOT:-${CARGO_HOME:-$HOME/.cargo}}/bin}
target=${CARGO_TARGET_DIR:-target}
cargo build --release --locked
mkdir -p "$dir"
for b in gridswarm world-server robot-agent; do
    install -m 0755 "$target/release/$b" "$dir/$b"
done
echo "installed gridswarm, world-server and robot-agent in $dir"
case ":$PATH:" in
    *":$dir:"*) ;;
    *) echo "$dir is not on PATH: add it, or call the programs by their path" >&2 ;;
esac
