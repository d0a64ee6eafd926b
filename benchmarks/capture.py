"""Capture throughput and timing against a fake glove on a pseudo-terminal.

    python benchmarks/capture.py [--rate 1000] [--duration 600]

The fake glove (flexcal.synthetic.device, in its own process) streams the protocol at
--rate lines per second with a drifting device clock; flexcal's SerialReader and
TrialRecorder record it to a temporary trial folder, as `flexcal capture` does. Prints
lines sent / received / lost, unreadable lines, peak memory of the recording process,
the clock fit (drift, latency after the fit) and the error of each sample's t_s against
the host time it was generated at, compared with the sample period.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

CHILD = r"""
import sys, time, json
from flexcal.synthetic.device import FakeGlove
from flexcal.synthetic.sensor import DeviceClock
rate, duration = float(sys.argv[1]), float(sys.argv[2])
g = FakeGlove([(0, 45000.0), (duration / 2, 60000.0)], rate_hz=rate, noise_ohm=40,
              clock=DeviceClock(boot_ms=3000, drift_ppm=40))
print(g.port, flush=True)
sys.stdin.readline()            # the parent has opened the port
g.start()
print(json.dumps({"t0": g.t0}), flush=True)
time.sleep(duration)
g.stop()
print(json.dumps({"sent": g.lines_sent}), flush=True)
"""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rate", type=float, default=1000.0)
    ap.add_argument("--duration", type=float, default=600.0)
    args = ap.parse_args()

    from flexcal.capture.serial_reader import SerialReader
    from flexcal.capture.session import TrialRecorder

    child = subprocess.Popen([sys.executable, "-c", CHILD, str(args.rate), str(args.duration)],
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    port = child.stdout.readline().strip()
    with tempfile.TemporaryDirectory() as tmp:
        rec = TrialRecorder(Path(tmp) / "trial", meta={"port": port, "benchmark": True})
        with SerialReader(port, max_line=1024) as reader:
            child.stdin.write("go\n")
            child.stdin.flush()
            t0 = json.loads(child.stdout.readline())["t0"]
            print(f"recording {args.rate:g} lines/s for {args.duration:g} s from a fake glove on {port} ...",
                  flush=True)
            end = time.monotonic() + args.duration + 2.0
            next_report = time.monotonic() + 60
            while time.monotonic() < end:
                item = reader.get(timeout=0.05)
                while item is not None:
                    rec.handle(item)
                    item = reader.get(timeout=0)
                if time.monotonic() > next_report:
                    print(f"  {rec.samples} samples so far, queue {reader.queue.qsize()}", flush=True)
                    next_report += 60
        sent = json.loads(child.stdout.readline())["sent"]
        child.wait(timeout=10)
        summary = rec.finish()
        peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024   # before this script's own analysis
        df = pd.read_csv(Path(tmp) / "trial" / "serial.csv")
    # when each sample was generated, on the host clock: invert the device clock
    t_gen = t0 + (df["t_device_ms"].to_numpy(float) - 3000) / 1000.0 / (1 + 40e-6)
    err_ms = 1000 * (df["t_s"].to_numpy() - t_gen)
    period_ms = 1000 / args.rate
    lat = summary["clock_fit"]["latency_after_fit"]
    print(f"lines sent {sent}, received {summary['samples']}, lost {sent - summary['samples']}, "
          f"unreadable {summary['unreadable_lines']}, events {len(summary['events'])}")
    print(f"peak memory of the recording process: {peak_mb:.0f} MB")
    print(f"clock fit: drift {summary['clock_fit']['drift_ppm']:+.1f} ppm (true -40.0); USB latency after the fit "
          f"median {1000 * lat['median_s']:.2f} ms, p95 {1000 * lat['p95_s']:.2f} ms, max {1000 * lat['max_s']:.1f} ms")
    print(f"sample time error (t_s - generated): median {np.median(err_ms):+.2f} ms, "
          f"p95 |err| {np.percentile(np.abs(err_ms), 95):.2f} ms, max |err| {np.abs(err_ms).max():.2f} ms; "
          f"sample period {period_ms:.2f} ms (t_ms itself has 1 ms resolution)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
