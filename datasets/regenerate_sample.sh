#!/usr/bin/env bash
# Regenerates datasets/sample bit for bit (same flexcal, NumPy and OpenCV versions as
# recorded in datasets/sample/experiment.json and README.md).
set -euo pipefail
cd "$(dirname "$0")"
rm -rf sample.new
flexcal render --out sample.new --trials 5 --angles 0:90:10 --difficulty realistic --seed 2026 --size 1280x960 --jpeg-quality 85
cp sample/README.md sample.new/README.md
rm -rf sample
mv sample.new sample
