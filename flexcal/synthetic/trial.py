"""Simulated experiments: trial folders (DESIGN.md) and the pressure experiment table.

A trial holds the finger at each step angle, with smooth transitions between holds,
takes a photo in the middle of each hold, and records the glove's stream. Everything is
drawn from one seed, so an experiment regenerates bit for bit (same flexcal, OpenCV and
NumPy versions).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import datetime, timedelta, timezone
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
from tqdm import tqdm

from flexcal import __version__
from flexcal.calibration import reference
from flexcal.calibration.models import pressure_from_mass
from flexcal.divider import Divider
from flexcal.synthetic.render import render_finger
from flexcal.synthetic.sensor import DeviceClock, SensorModel, banner_lines, simulate_readings

_EPOCH = datetime(2026, 1, 5, 9, 0, 0, tzinfo=timezone.utc)


@dataclass(frozen=True)
class TrialPlan:
    """Timing of a trial: holds at each angle with ramps between. Times in seconds."""

    angles_deg: tuple = tuple(range(0, 91, 10))
    hold_s: float = 4.0
    ramp_s: float = 1.5
    lead_s: float = 1.0
    rate_hz: float = 50.0
    angle_jitter_deg: float = 1.0     # how far the held angle lands from the target (1 sigma)
    photo_jitter_s: float = 0.3       # when in the hold the photo is taken, around its middle

    def __post_init__(self):
        if len(self.angles_deg) == 0:
            raise ValueError("angles_deg must hold at least one angle")
        for a in self.angles_deg:
            if not 0 <= a <= 180:
                raise ValueError(f"angles_deg must lie within 0...180 degrees, got {a!r}")
        for name in ("hold_s", "rate_hz"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be positive, got {getattr(self, name)!r}")
        for name in ("ramp_s", "lead_s", "angle_jitter_deg", "photo_jitter_s"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be non-negative, got {getattr(self, name)!r}")


def angle_schedule(plan: TrialPlan, rng):
    """True angle over time and the photo moments.

    Returns ``(t_s, angle_deg, steps)`` where steps is a DataFrame with one row per
    hold: ``step, target_deg, angle_deg, hold_start_s, hold_end_s, photo_t_s``.
    """
    held = np.asarray(plan.angles_deg, float) + rng.normal(0, plan.angle_jitter_deg, len(plan.angles_deg))
    held = np.clip(held, 0, 180)
    holds = plan.hold_s * rng.uniform(0.85, 1.2, len(held))
    rows, t0 = [], plan.lead_s
    for i, (target, a, h) in enumerate(zip(plan.angles_deg, held, holds)):
        photo = t0 + h / 2 + rng.uniform(-1, 1) * min(plan.photo_jitter_s, h / 4)
        rows.append(dict(step=i + 1, target_deg=float(target), angle_deg=float(a),
                         hold_start_s=t0, hold_end_s=t0 + h, photo_t_s=float(photo)))
        t0 += h + plan.ramp_s
    steps = pd.DataFrame(rows)
    t_end = steps["hold_end_s"].iloc[-1] + plan.lead_s
    t = np.arange(0.0, t_end, 1.0 / plan.rate_hz)
    angle = np.full_like(t, held[0])
    for i in range(len(steps)):
        s = steps.iloc[i]
        angle[t >= s.hold_start_s] = s.angle_deg
        if i + 1 < len(steps):
            nxt = steps.iloc[i + 1]
            ramp = (t > s.hold_end_s) & (t < nxt.hold_start_s)
            x = (t[ramp] - s.hold_end_s) / (nxt.hold_start_s - s.hold_end_s)
            angle[ramp] = s.angle_deg + (nxt.angle_deg - s.angle_deg) * (1 - np.cos(np.pi * x)) / 2
    return t, angle, steps


def simulate_trial(out_dir, *, plan: TrialPlan = TrialPlan(), difficulty: str = "realistic", rng=None,
                   shape=(960, 1280), jpeg_quality: int = 90, sensor: SensorModel = SensorModel(),
                   divider: Divider = Divider(), trial_index: int = 1, progress=None, render_overrides=None) -> dict:
    """Write one trial folder: images/, frames.csv, serial.csv, meta.json and truth.csv.

    Returns a summary dict (folder, number of photos and samples).
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(0 if rng is None else rng)
    out = Path(out_dir)
    (out / "images").mkdir(parents=True, exist_ok=True)
    t, angle, steps = angle_schedule(plan, rng)
    readings = simulate_readings(t, angle, model=sensor, divider=divider, rng=rng)
    clock = DeviceClock(boot_ms=int(rng.integers(1_500, 6_000)), drift_ppm=float(rng.uniform(-80, 80)))
    host0 = float(rng.uniform(1_000, 50_000))  # host monotonic clock at t = 0
    latency = 0.001 + rng.exponential(0.0015, len(t))
    serial = pd.DataFrame({
        "t_s": np.round(host0 + t, 6),
        "t_host_s": np.round(host0 + t + latency, 6),
        "t_device_ms": clock.t_ms(t),
        "adc": readings["adc"].round(2),
        "resistance_ohm": readings["resistance_ohm"].round(1),
        "angle_deg": readings["angle_deg"].round(2),
    })
    serial.to_csv(out / "serial.csv", index=False)

    frames, truth = [], []
    # the photo is compressed once, when it is saved, as a camera would
    overrides = {"jpeg_quality": None, **(render_overrides or {})}
    for _, s in steps.iterrows():
        name = f"step_{int(s.step):02d}_{int(round(s.target_deg)):03d}deg.jpg"
        img, tr = render_finger(s.angle_deg, shape=shape, rng=rng, difficulty=difficulty, **overrides)
        cv2.imwrite(str(out / "images" / name), img, [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)])
        i = int(np.argmin(np.abs(t - s.photo_t_s)))
        frames.append(dict(image=name, t_s=round(host0 + s.photo_t_s, 6), step=int(s.step), target_deg=s.target_deg))
        truth.append(dict(image=name, t_s=host0 + s.photo_t_s, step=int(s.step), target_deg=s.target_deg,
                          angle_deg=s.angle_deg, vertex_x=tr.vertex_xy[0], vertex_y=tr.vertex_xy[1],
                          resistance_true_ohm=readings["resistance_true_ohm"].iloc[i],
                          resistance_static_ohm=float(sensor.resistance_ohm(s.angle_deg)),
                          hold_start_s=host0 + s.hold_start_s, hold_end_s=host0 + s.hold_end_s,
                          difficulty=difficulty, roll_deg=tr.params.roll_deg, mirror=tr.params.mirror,
                          glove=tr.params.glove or "", pip_deg=tr.params.pip_deg))
        if progress is not None:
            progress.update(1)
    pd.DataFrame(frames).to_csv(out / "frames.csv", index=False)
    pd.DataFrame(truth).to_csv(out / "truth.csv", index=False, float_format="%.6f")
    meta = {
        "port": "simulated", "baud": 115200, "camera": "flexcal.synthetic.render_finger",
        "firmware_banner": [line.lstrip("# ") for line in banner_lines(divider, rate_hz=plan.rate_hz)],
        "flexcal_version": __version__,
        "start_time": (_EPOCH + timedelta(hours=trial_index)).isoformat(),
        "clock": {"source": "simulated", "boot_ms": clock.boot_ms, "drift_ppm": clock.drift_ppm},
        "simulation": {"difficulty": difficulty, "angles_deg": list(plan.angles_deg), "hold_s": plan.hold_s,
                       "ramp_s": plan.ramp_s, "rate_hz": plan.rate_hz, "image_shape": list(shape),
                       "jpeg_quality": jpeg_quality, "sensor": sensor.__dict__, "divider": divider.__dict__},
    }
    (out / "meta.json").write_text(json.dumps(meta, indent=2, default=float) + "\n")
    return {"folder": str(out), "photos": len(frames), "samples": len(serial)}


def simulate_pressure(path=None, *, masses_g=reference.PRESSURE_MASSES_G, repeats: int = reference.PRESSURE_REPEATS,
                      contact_area_in2: float = reference.CONTACT_AREA_IN2,
                      angle_noise_deg: float = 0.8, resistance_noise_ohm: float = 350.0, rng=None) -> pd.DataFrame:
    """The pressure experiment: weights on a foam pad pressing the bare sensor.

    Defaults reproduce the reference fits theta = 4.342 p + 25.39 and R = 2540 p + 45 880
    (p in psi). Returns (and writes to ``path`` if given) the table
    ``mass_g, trial, angle_deg, resistance_ohm``.
    """
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(0 if rng is None else rng)
    if angle_noise_deg < 0 or resistance_noise_ohm < 0:
        raise ValueError("angle_noise_deg and resistance_noise_ohm must be non-negative")
    rows = []
    for trial in range(1, int(repeats) + 1):
        for m in masses_g:
            p_psi, _ = pressure_from_mass(m, contact_area_in2)
            rows.append(dict(
                mass_g=float(m), trial=trial,
                angle_deg=float(np.polyval(reference.ANGLE_VS_PRESSURE, p_psi) + rng.normal(0, angle_noise_deg)),
                resistance_ohm=float(np.polyval(reference.RESISTANCE_VS_PRESSURE, p_psi)
                                     + rng.normal(0, resistance_noise_ohm)),
            ))
    df = pd.DataFrame(rows)
    if path is not None:
        df.to_csv(path, index=False, float_format="%.3f")
    return df


def write_experiment(out_dir, *, trials: int = 5, angles_deg=tuple(range(0, 91, 10)), difficulty: str = "realistic",
                     seed: int = 0, shape=(960, 1280), jpeg_quality: int = 90, show_progress: bool = True) -> dict:
    """Write ``trial_01 ... trial_NN`` folders and ``pressure.csv`` under ``out_dir``.

    Each trial and the pressure table draw from their own child of ``seed``.
    """
    if int(trials) < 1:
        raise ValueError(f"trials must be at least 1, got {trials!r}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plan = TrialPlan(angles_deg=tuple(float(a) for a in angles_deg))
    children = np.random.SeedSequence(int(seed)).spawn(int(trials) + 1)
    summary = {"trials": []}
    with tqdm(total=int(trials) * len(plan.angles_deg), desc="rendering", unit="photo",
              disable=not show_progress) as bar:
        for i in range(int(trials)):
            summary["trials"].append(simulate_trial(
                out / f"trial_{i + 1:02d}", plan=plan, difficulty=difficulty, rng=np.random.default_rng(children[i]),
                shape=shape, jpeg_quality=jpeg_quality, trial_index=i + 1, progress=bar))
    simulate_pressure(out / "pressure.csv", rng=np.random.default_rng(children[-1]))
    summary["pressure"] = str(out / "pressure.csv")
    (out / "experiment.json").write_text(json.dumps({
        "generator": "flexcal render", "flexcal_version": __version__, "seed": int(seed), "trials": int(trials),
        "angles_deg": [float(a) for a in angles_deg], "difficulty": difficulty, "image_shape": list(shape),
        "jpeg_quality": int(jpeg_quality),
    }, indent=2) + "\n")
    return summary
