"""Plateaus and pairing on simulated trials: frames.csv, EXIF and plateau order."""

import shutil

import numpy as np
import pandas as pd
import pytest
from PIL import Image

from flexcal.calibration.pairing import pair_trial, read_frames
from flexcal.capture.logs import read_log
from flexcal.capture.plateaus import find_plateaus
from flexcal.errors import FlexcalError


def _trial(root, name="trial_01"):
    d = root / name
    images = sorted((d / "images").iterdir())
    truth = pd.read_csv(d / "truth.csv")
    angles = pd.DataFrame({"angle_deg": truth["angle_deg"], "angle_unc_deg": 0.5, "status": "ok", "reason": ""})
    return d, images, truth, angles


def test_plateaus_are_the_holds(experiment):
    d, _, truth, _ = _trial(experiment)
    s = read_log(d / "serial.csv")
    p = find_plateaus(s["t_s"], s["resistance_ohm"])
    assert len(p) == len(truth)
    # every photo falls inside its own plateau, and the plateau's level is the settled resistance
    assert ((truth["t_s"] >= p["t_start_s"]) & (truth["t_s"] <= p["t_end_s"])).all()
    np.testing.assert_allclose(p["resistance_ohm"], truth["resistance_static_ohm"], atol=60)


def test_pairing_by_frames_takes_the_steady_median(experiment):
    d, images, truth, angles = _trial(experiment)
    pairs, notes = pair_trial("trial_01", images, angles, read_log(d / "serial.csv"),
                              frames=read_frames(d / "frames.csv"))
    assert pairs["steady"].all() and (pairs["time_source"] == "frames.csv").all()
    assert (pairs["n_samples"] >= 50).all()
    # median of ~100 samples of 40-ohm noise: within 30 ohm of the true settled resistance
    np.testing.assert_allclose(pairs["resistance_ohm"], truth["resistance_true_ohm"], atol=30)
    np.testing.assert_allclose(pairs["angle_measured_deg"], (pairs["resistance_ohm"] - 31250) / 577.9, atol=0.02)
    assert notes == []


def test_pairing_in_plateau_order_without_frames(experiment):
    d, images, truth, angles = _trial(experiment)
    pairs, _ = pair_trial("trial_01", images, angles, read_log(d / "serial.csv"))
    assert (pairs["time_source"] == "plateau order").all()
    np.testing.assert_allclose(pairs["resistance_ohm"], truth["resistance_static_ohm"], atol=60)


def test_pairing_by_exif_times_on_another_clock(experiment, tmp_path):
    d, images, truth, angles = _trial(experiment)
    camera_t0 = pd.Timestamp("2025-06-01 14:03:07")
    copies = []
    for img, t in zip(images, truth["t_s"]):
        stamp = camera_t0 + pd.Timedelta(seconds=float(t - truth["t_s"].iloc[0]))
        exif = Image.Exif()
        exif.get_ifd(0x8769)[0x9003] = stamp.strftime("%Y:%m:%d %H:%M:%S")
        out = tmp_path / img.name
        Image.open(img).save(out, exif=exif)
        copies.append(out)
    pairs, notes = pair_trial("trial_01", copies, angles, read_log(d / "serial.csv"))
    assert (pairs["time_source"] == "EXIF").all()
    assert any("10/10 inside plateaus" in n for n in notes)
    assert pairs["steady"].all()
    np.testing.assert_allclose(pairs["resistance_ohm"], truth["resistance_static_ohm"], atol=60)


def test_more_photos_than_plateaus_is_a_clear_error(experiment, tmp_path):
    d, images, truth, angles = _trial(experiment)
    extra = tmp_path / "zz_extra.jpg"
    shutil.copy(images[0], extra)
    a = pd.concat([angles, angles.iloc[:1]], ignore_index=True)
    with pytest.raises(FlexcalError, match="11 photo.*10 steady plateau"):
        pair_trial("trial_01", images + [extra], a, read_log(d / "serial.csv"))


def test_time_going_backwards_is_named(experiment, tmp_path):
    d, images, _, angles = _trial(experiment)
    s = pd.read_csv(d / "serial.csv")
    s.loc[1500:, "t_s"] -= 20.0   # the log restarts its clock
    s.to_csv(tmp_path / "serial.csv", index=False)
    with pytest.raises(FlexcalError, match="time goes backwards at line 1502"):
        pair_trial("trial_01", images, angles, read_log(tmp_path / "serial.csv"),
                   frames=read_frames(d / "frames.csv"))


def test_photos_outside_the_log_get_no_samples_and_a_note(experiment):
    d, images, _, angles = _trial(experiment)
    frames = read_frames(d / "frames.csv")
    frames["t_s"] += 10_000.0   # frames on another clock
    pairs, notes = pair_trial("trial_01", images, angles, read_log(d / "serial.csv"), frames=frames)
    assert pairs["resistance_ohm"].isna().all() and not pairs["steady"].any()
    assert any("no serial samples" in n and "one clock" in n for n in notes)


def test_unsteady_photo_is_flagged(experiment):
    d, images, truth, angles = _trial(experiment)
    frames = read_frames(d / "frames.csv")
    # move the 3rd photo into the ramp after its hold
    frames.loc[2, "t_s"] = truth.loc[2, "hold_end_s"] + 0.75
    pairs, _ = pair_trial("trial_01", images, angles, read_log(d / "serial.csv"), frames=frames, window_s=1.0)
    assert pairs["steady"].tolist() == [True, True, False] + [True] * 7
