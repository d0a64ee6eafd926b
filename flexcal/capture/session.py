"""Recording a trial: serial samples and photos on one clock, into a trial folder.

``TrialRecorder`` turns the reader's lines into rows of ``serial.csv`` (appended and
flushed one by one, so a killed session leaves a readable file), maps the device clock
onto the host clock online, and saves photos with their time in ``frames.csv``.
``run_capture`` walks the steps: in auto mode a photo is taken once the reading has
been steady for ``hold_s`` at a new level; in manual mode when the user presses Enter.
"""

from __future__ import annotations

import json
import math
import os
import queue
import sys
import threading
import time
from datetime import datetime, timezone
from pathlib import Path

import cv2
import numpy as np
import pandas as pd

from flexcal import __version__
from flexcal.capture.clock import ClockFit
from flexcal.capture.logs import SAMPLE_COLUMNS, parse_text_line
from flexcal.capture.plateaus import SteadyTracker
from flexcal.capture.protocol import Comment, Header, Sample, parse_line
from flexcal.capture.serial_reader import Event, Line
from flexcal.divider import factory_angle_deg
from flexcal.errors import FlexcalError

FRAME_COLUMNS = ["image", "t_s", "step", "target_deg", "frame_index", "resistance_ohm"]


def _num(x, digits):
    return "" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.{digits}f}"


def parse_live_line(text: str):
    """A line from a device: the firmware protocol, else what ``read_log``'s dialects hold
    (``Resistance: 45000 ohms``, a bare number). Returns a Sample (``t_ms`` -1 when the
    line has no device time), Comment, Header or None; ValueError when unreadable."""
    try:
        return parse_line(text)
    except ValueError:
        values = parse_text_line(text)
        if values is None or "resistance_ohm" not in values:
            raise
        r = values["resistance_ohm"]
        return Sample(-1, values.get("adc", float("nan")), r, values.get("angle_deg", float(factory_angle_deg(r))))


class TrialRecorder:
    """Writes one trial folder (DESIGN.md) as data arrives."""

    def __init__(self, out_dir, *, meta: dict, window_s: float = 0.5):
        self.out = Path(out_dir)
        if self.out.exists() and any(self.out.iterdir()):
            raise FlexcalError(f"--out {self.out}: folder is not empty; choose a new trial folder "
                               "(nothing recorded is ever overwritten)")
        (self.out / "images").mkdir(parents=True, exist_ok=True)
        self.meta = {"flexcal_version": __version__, "start_time": datetime.now(timezone.utc).isoformat(), **meta,
                     "firmware_banner": []}
        self.clock = ClockFit()
        self.tracker = SteadyTracker(window_s=window_s)
        self.samples = 0
        self.bad_lines = 0
        self.bad_examples: list[str] = []
        self.header_seen = False
        self.events: list[str] = []
        self.last: dict = {}
        self.photos = 0
        self._serial = open(self.out / "serial.csv", "w", newline="")
        self._serial.write(",".join(SAMPLE_COLUMNS) + "\n")
        self._serial.flush()
        self._frames = open(self.out / "frames.csv", "w", newline="")
        self._frames.write(",".join(FRAME_COLUMNS) + "\n")
        self._frames.flush()
        self._write_meta()

    def _write_meta(self, extra: dict | None = None) -> None:
        data = {**self.meta, **(extra or {})}
        tmp = self.out / "meta.json.tmp"
        tmp.write_text(json.dumps(data, indent=2, default=str) + "\n")
        os.replace(tmp, self.out / "meta.json")

    def handle(self, item) -> dict | None:
        """Take one Line or Event; returns the sample's values when it was a sample."""
        if isinstance(item, Event):
            self.events.append(f"{item.kind} at {item.t_host_s:.3f} s: {item.detail}")
            return None
        if not isinstance(item, Line):
            return None
        try:
            p = parse_live_line(item.text)
        except ValueError as e:
            self.bad_lines += 1
            if len(self.bad_examples) < 5:
                self.bad_examples.append(f"{item.text[:40]!r}: {e}")
            return None
        if p is None:
            return None
        if isinstance(p, Comment):
            if not self.header_seen:
                self.meta["firmware_banner"].append(p.text)
            else:
                self.events.append(f"device at {item.t_host_s:.3f} s: {p.text}")
            return None
        if isinstance(p, Header):
            self.header_seen = True
            self._write_meta()
            return None
        t_host = item.t_host_s
        if p.t_ms >= 0:
            self.clock.add(p.t_ms / 1000.0, t_host)
            t_s = float(self.clock.host_time(p.t_ms / 1000.0))
        else:
            t_s = t_host
        self._serial.write(f"{t_s:.6f},{t_host:.6f},{p.t_ms if p.t_ms >= 0 else ''},{_num(p.adc, 2)},"
                           f"{_num(p.resistance_ohm, 1)},{_num(p.angle_deg, 2)}\n")
        self._serial.flush()
        self.samples += 1
        self.tracker.update(t_s, p.resistance_ohm)
        self.last = {"t_s": t_s, "resistance_ohm": p.resistance_ohm, "angle_deg": p.angle_deg}
        return self.last

    def take_photo(self, frame: np.ndarray, t_s: float, *, step: int, target_deg: float, frame_index: int = -1,
                   name: str | None = None) -> str:
        name = name or f"step_{step:02d}_{int(round(target_deg)):03d}deg.png"
        path = self.out / "images" / name
        if not cv2.imwrite(str(path), frame):
            raise FlexcalError(f"{path}: could not write the photo (disk full?)")
        r = self.tracker.level()
        self._frames.write(f"{name},{t_s:.6f},{step},{target_deg:g},{frame_index},{_num(r, 1)}\n")
        self._frames.flush()
        self.photos += 1
        return name

    def finish(self) -> dict:
        """Close the files; rewrite serial.csv's t_s with the final clock fit; write meta.json."""
        for f in (self._serial, self._frames):
            if not f.closed:
                f.flush()
                f.close()
        clock = self.clock.summary() if self.clock.offset is not None else None
        if clock is not None and self.samples:
            # every sample's t_s from the final fit, in chunks (a long session does not fit in memory)
            tmp = self.out / "serial.csv.tmp"
            with open(tmp, "w", newline="") as f:
                for i, df in enumerate(pd.read_csv(self.out / "serial.csv", chunksize=200_000)):
                    has_dev = df["t_device_ms"].notna()
                    df.loc[has_dev, "t_s"] = self.clock.host_time(
                        df.loc[has_dev, "t_device_ms"].to_numpy(float) / 1000.0)
                    df.to_csv(f, index=False, header=i == 0, float_format="%.6f")
            os.replace(tmp, self.out / "serial.csv")
        summary = {"samples": self.samples, "photos": self.photos, "unreadable_lines": self.bad_lines,
                   "unreadable_examples": self.bad_examples, "events": self.events, "clock_fit": clock,
                   "end_time": datetime.now(timezone.utc).isoformat()}
        self._write_meta(summary)
        return summary


class _StdinLines:
    """Lines typed by the user, read on a thread (so the readout keeps updating)."""

    def __init__(self, stream=None):
        self.q: queue.Queue = queue.Queue()
        self.stream = stream or sys.stdin
        threading.Thread(target=self._run, daemon=True).start()

    def _run(self):
        for line in self.stream:
            self.q.put(line)

    def pressed(self) -> bool:
        try:
            self.q.get_nowait()
            return True
        except queue.Empty:
            return False


def run_capture(reader, frames, recorder: TrialRecorder, steps, *, mode: str = "auto", hold_s: float = 1.0,
                no_data_timeout_s: float = 5.0, out=None, keys=None, step_timeout_s: float | None = None):
    """Walk the steps and take a photo at each. Returns the recorder's summary.

    In auto mode a photo is taken once the signal has been steady for ``hold_s`` at a
    level different from the previous photo's; in manual mode when ``keys`` (default:
    stdin) delivers a line. Ctrl-C stops cleanly: everything recorded stays on disk.
    """
    if mode not in ("auto", "manual"):
        raise ValueError(f"mode must be 'auto' or 'manual', got {mode!r}")
    keys = keys if keys is not None else (_StdinLines() if mode == "manual" else None)
    out = out or sys.stdout
    tty = getattr(out, "isatty", lambda: False)()
    t_start = time.monotonic()
    last_level = None
    try:
        for k, target in enumerate(steps, start=1):
            print(f"step {k}/{len(steps)}: bend to {target:g} deg and hold still"
                  + (" -- photo when steady" if mode == "auto" else " -- press Enter for the photo"), file=out,
                  flush=True)
            t_step = time.monotonic()
            last_show = 0.0
            while True:
                item = reader.get(timeout=0.02)
                while item is not None:
                    recorder.handle(item)
                    item = reader.get(timeout=0)
                now = time.monotonic()
                if recorder.samples == 0 and now - t_start > no_data_timeout_s:
                    why = (f"only unreadable lines ({recorder.bad_lines}, e.g. {recorder.bad_examples[0]}); "
                           "wrong baud rate?") if recorder.bad_lines else "nothing at all"
                    raise FlexcalError(f"--port {reader.url}: no samples in {no_data_timeout_s:g} s ({why}); "
                                       "is the glove running the flexcal firmware?")
                if step_timeout_s is not None and now - t_step > step_timeout_s:
                    raise FlexcalError(f"step {k}: no steady reading within {step_timeout_s:g} s")
                tr = recorder.tracker
                level = tr.level()
                if tty and now - last_show > 0.2 and recorder.last:
                    print(f"\r  R {recorder.last['resistance_ohm']:9.1f} ohm  angle {recorder.last['angle_deg']:6.2f} "
                          f"deg  {'steady %.1f s' % tr.steady_for_s if tr.steady_for_s else 'moving'}     ",
                          end="", file=out, flush=True)
                    last_show = now
                if mode == "auto":
                    new_level = last_level is None or abs(level - last_level) > max(
                        6 * (tr.noise if np.isfinite(tr.noise) else 0.0), 2e-3 * abs(level))
                    ready = tr.steady_for_s >= hold_s and new_level
                else:
                    ready = keys.pressed()
                if ready:
                    frame, t_frame, index = frames.latest(after=now)
                    name = recorder.take_photo(frame, t_frame, step=k, target_deg=float(target), frame_index=index)
                    last_level = level
                    print(("\n" if tty else "") + f"  photo {name}: R {level:.1f} ohm", file=out, flush=True)
                    break
    except KeyboardInterrupt:
        summary = recorder.finish()
        print(f"\ninterrupted: {summary['photos']} photo(s) and {summary['samples']} samples kept in {recorder.out}",
              file=out)
        raise
    return recorder.finish()
