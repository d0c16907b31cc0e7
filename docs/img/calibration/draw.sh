#!/usr/bin/env bash
# Draws the calibration benchmark's figure of docs/calibration.md into this folder: the command
# `cargo xtask measure --only calibration-bench` runs for the table (`magbench calibrate bench`
# at its defaults, seed 0, in a release build), its `calibration-bench.svg` copied here. The
# benchmark's rigs are stepped frame by frame in process, so the figure does not depend on the
# machine or its load.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cd "$here/../../.."
out="$(mktemp -d)/bench"
cargo run -q --release -p magbench -- calibrate bench --out "$out" --threads 2 > /dev/null
cp "$out/calibration-bench.svg" "$here/calibration-bench.svg"
echo "drawn: $here/calibration-bench.svg"
