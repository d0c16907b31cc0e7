#!/usr/bin/env bash
# Draws the scaling plots of docs/suites.md into this folder: the scaling experiment and
# `magbench results scaling` for its three families, as `magbench docs measure --only scaling`
# runs them for the table, in a release build. Times are wall-clock: run it on an otherwise
# idle machine.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here/../../.."
magbench() { cargo run -q --release -p magbench -- "$@"; }
out="$(mktemp -d)/scaling"
magbench bench experiments/scaling.toml --out "$out" --threads 2 --quiet
magbench results scaling "$out" --family serpentine --by walls
magbench results scaling "$out" --family corridor --by length
magbench results scaling "$out" --family team --by agents
rm -f "$here"/scaling-*.svg "$here"/scaling-*.png
cp "$out"/plots/scaling-*.svg "$here/"
echo "drawn: $(cd "$here" && ls scaling-*.svg | tr '\n' ' ')"
