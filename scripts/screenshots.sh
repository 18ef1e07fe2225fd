#!/usr/bin/env bash
# Remakes docs/screenshots/: one PNG per picture the commands write (route
# map, replay page, and each experiment's report), as headless chromium
# shows them in a 940 px wide window, the narrowest the reports are made to
# read at (orchestrator/tests/browser.rs checks that width). With
# ImageMagick's `convert`, each is cut to 96 colours to keep it small.
# Usage: scripts/screenshots.sh  (from the repository's root, after a release build)
set -euo pipefail
g=./target/release/gridswarm
shots=docs/screenshots
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$shots"

shoot() { # NAME URL HEIGHT
    local profile="$work/profile"
    rm -rf "$profile"
    chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --disable-dev-shm-usage \
        --user-data-dir="$profile" --window-size="940,$3" --screenshot="$work/$1.png" "$2" 2>/dev/null
    if convert -version 2>/dev/null | grep -q ImageMagick; then
        convert "$work/$1.png" -colors 96 "PNG8:$shots/$1.png"
    else
        cp "$work/$1.png" "$shots/$1.png"
    fi
    echo "wrote $shots/$1.png"
}

$g simulate --robots 6 --seed 3 --kill 2@20 --freeze 4@10:30 --freeze 5@40 --loss 0.1 --retries 2 \
    --out "$work/run" >/dev/null
shoot routes "file://$work/run/routes.svg" 900
shoot replay "file://$work/run/replay.html#round=60&paused=1" 900
$g experiment --runs 20 --robots 1-8 --out "$work/fig7" >/dev/null
shoot fig7 "file://$work/fig7/report.html" 1100
$g experiment --scenario random:1 --maps 4 --runs 5 --robots 1-4 --out "$work/maps" >/dev/null
# Headless chromium draws a page opened at an anchor blank: the maps'
# section is shown in a frame instead.
cat >"$work/maps/shot.html" <<'HTML'
<!DOCTYPE html><html><body style="margin:0"><iframe src="report.html#maps" style="border:0;width:940px;height:640px"></iframe></body></html>
HTML
shoot maps "file://$work/maps/shot.html" 640
$g experiment --grids --out "$work/grids" >/dev/null
shoot grids "file://$work/grids/grids.html" 1100
$g experiment failures --runs 50 --out "$work/failures" >/dev/null
shoot failures "file://$work/failures/report.html" 1500
$g experiment radio --runs 10 --out "$work/radio" >/dev/null
shoot radio "file://$work/radio/report.html" 1100
$g experiment readings --robots 1-4 --runs 5 --seeds 1 --out "$work/readings" >/dev/null
shoot readings "file://$work/readings/report.html" 1100
$g experiment scale --robots 2,4 --runs 1 --out "$work/scale" >/dev/null 2>&1
shoot scale "file://$work/scale/report.html" 1100
