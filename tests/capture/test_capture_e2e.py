"""End to end: a glove (the real firmware in simavr, or the Python fake) and a rendered video as the
camera -> `flexcal capture --auto` -> `calibrate` on the trial it wrote."""

import json

import cv2
import numpy as np
import pandas as pd
import pytest

from flexcal.cli import main
from flexcal.divider import Divider
from flexcal.synthetic import render_finger
from flexcal.synthetic.device import FakeGlove
from flexcal.synthetic.sensor import SensorModel

ANGLES = (0, 20, 40, 60, 80)
HOLD_S, LEAD_S, FPS = 3.5, 1.0, 5


def _step_at(t_s):
    """Which step is held at time t_s: step k from LEAD_S + HOLD_S * k on (step 0 from the start)."""
    return int(np.clip(np.floor((t_s - LEAD_S) / HOLD_S), 0, len(ANGLES) - 1))


def _video(path, rng):
    """The finger at each step's angle on the same timeline as the resistance script."""
    n = int((LEAD_S + HOLD_S * len(ANGLES) + 3) * FPS)
    frames = {a: render_finger(float(a), shape=(240, 320), rng=rng, difficulty="clean")[0] for a in ANGLES}
    w = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), FPS, (320, 240))
    for k in range(n):
        w.write(frames[ANGLES[_step_at(k / FPS)]])
    w.release()


def _script():
    """The sensor's resistance on the same timeline as the video (the reference's sensor)."""
    m = SensorModel()
    return [(0.0 if k == 0 else LEAD_S + HOLD_S * k, float(m.resistance_ohm(a))) for k, a in enumerate(ANGLES)]


@pytest.mark.slow
@pytest.mark.parametrize("device", ["simavr", "fake"])
def test_capture_then_calibrate(device, tmp_path):
    script = _script()
    video = tmp_path / "camera.avi"
    _video(video, np.random.default_rng(8))
    trial = tmp_path / "trial_01"
    args = ["--camera", str(video), "--out", str(trial), "--steps", "0:80:20", "--hold-s", "1.0",
            "--step-timeout-s", "30"]
    if device == "simavr":
        from sim_glove import build, simulated_glove

        build()
        with simulated_glove("".join(f"{t} {r}\n" for t, r in script), tmp_path) as pty:
            assert main(["capture", "--port", pty, *args]) == 0
    else:
        glove = FakeGlove(script, noise_ohm=0.0)
        glove.start(delay_s=0.3)
        try:
            assert main(["capture", "--port", glove.port, *args]) == 0
        finally:
            glove.stop()

    frames = pd.read_csv(trial / "frames.csv")
    assert list(frames["step"]) == [1, 2, 3, 4, 5]
    # every photo shows its step: the video frame captured belongs to the step being held
    shown = [ANGLES[_step_at(i / FPS)] for i in frames["frame_index"]]
    assert shown == list(ANGLES)
    angles = pd.DataFrame({"image": [str(trial / "images" / n) for n in frames["image"]], "angle_deg": shown,
                           "angle_unc_deg": 0.5})
    angles.to_csv(tmp_path / "angles.csv", index=False)
    out = tmp_path / "cal"
    assert main(["calibrate", "--images", str(trial / "images"), "--log", str(trial / "serial.csv"),
                 "--angles", str(tmp_path / "angles.csv"), "--out", str(out)]) == 0
    pairs = pd.read_csv(out / "pairs.csv")
    assert pairs["steady"].all() and pairs["used"].all() and len(pairs) == 5
    # the pairs match the script: resistance within one ADC step of the scripted value
    d = Divider()
    for (_, p), (_, r) in zip(pairs.iterrows(), script):
        adc = np.floor(d.adc_from_resistance(r))
        assert d.resistance_from_adc(adc - 1) <= p["resistance_ohm"] <= d.resistance_from_adc(adc + 1), (p, r)
    data = json.loads((out / "calibration.json").read_text())
    assert data["pairs"]["used"] == 5
    assert "single trial" in " ".join(data["notes"]) or "only one trial" in " ".join(data["notes"])
