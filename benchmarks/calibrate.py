"""Wall time of `calibrate` on the shipped sample (target: <= 10 s on the 2-core machine, report included).

    python benchmarks/calibrate.py [--repeat 3] [--jobs N]

Runs the whole command as a user would (photos measured by flexcal.vision, overlays,
pressure experiment, figures, report.html, header) into a temporary folder, and prints
the time of each run and the validation figures of the last one.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

SAMPLE = Path(__file__).resolve().parent.parent / "datasets" / "sample"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=None)
    args = ap.parse_args()
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.repeat):
            out = Path(tmp) / f"run{i}"
            cmd = [sys.executable, "-m", "flexcal", "calibrate", "--trials", str(SAMPLE),
                   "--pressure", str(SAMPLE / "pressure.csv"), "--out", str(out)]
            if args.jobs:
                cmd += ["--jobs", str(args.jobs)]
            t0 = time.perf_counter()
            subprocess.run(cmd, check=True, capture_output=True)
            times.append(time.perf_counter() - t0)
            print(f"run {i + 1}: {times[-1]:.2f} s")
        data = json.loads((out / "calibration.json").read_text())
    print(f"calibrate on datasets/sample (5 trials, 50 photos, report included): "
          f"best {min(times):.2f} s, median {sorted(times)[len(times) // 2]:.2f} s (target <= 10 s)")
    print(f"pairs used: {data['pairs']['used']} of {data['pairs']['total']}")
    for v in data["validation"]:
        print(f"  {v['mapping']:9s} RMSE {v['rmse_deg']:.2f} deg  bias {v['bias_deg']:+.2f}  "
              f"max {v['max_abs_deg']:.2f}  ({v['validation']})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
