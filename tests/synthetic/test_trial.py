import hashlib
import json

import numpy as np
import pandas as pd
import pytest

from flexcal.calibration import reference
from flexcal.calibration.models import pressure_from_mass
from flexcal.cli import main
from flexcal.capture.logs import SAMPLE_COLUMNS
from flexcal.synthetic.trial import TrialPlan, simulate_pressure, write_experiment

SMALL = (240, 320)


@pytest.fixture(scope="module")
def experiment(tmp_path_factory):
    out = tmp_path_factory.mktemp("exp")
    write_experiment(out, trials=2, angles_deg=(0, 30, 60, 90), seed=11, shape=SMALL, show_progress=False)
    return out


def test_experiment_folders_follow_the_design_contract(experiment):
    assert sorted(p.name for p in experiment.iterdir()) == ["experiment.json", "pressure.csv", "trial_01", "trial_02"]
    for trial in ("trial_01", "trial_02"):
        d = experiment / trial
        assert {p.name for p in d.iterdir()} == {"images", "frames.csv", "serial.csv", "meta.json", "truth.csv"}
        frames = pd.read_csv(d / "frames.csv")
        assert list(frames.columns[:2]) == ["image", "t_s"] and {"step", "target_deg"} <= set(frames.columns)
        assert sorted(frames["image"]) == sorted(p.name for p in (d / "images").iterdir())
        serial = pd.read_csv(d / "serial.csv")
        assert list(serial.columns) == SAMPLE_COLUMNS
        assert serial["t_s"].is_monotonic_increasing and serial["t_device_ms"].is_monotonic_increasing
        assert (serial["t_host_s"] > serial["t_s"]).all()  # arrival after sampling
        # one clock: every photo falls inside the serial recording
        assert frames["t_s"].between(serial["t_s"].min(), serial["t_s"].max()).all()
        meta = json.loads((d / "meta.json").read_text())
        assert {"port", "baud", "camera", "firmware_banner", "flexcal_version", "start_time"} <= set(meta)


def test_photos_are_taken_while_the_angle_is_held(experiment):
    truth = pd.read_csv(experiment / "trial_01" / "truth.csv")
    assert truth["t_s"].between(truth["hold_start_s"], truth["hold_end_s"]).all()
    assert np.abs(truth["angle_deg"] - truth["target_deg"]).max() < 5
    serial = pd.read_csv(experiment / "trial_01" / "serial.csv")
    for _, row in truth.iterrows():
        near = serial[(serial["t_s"] > row.t_s - 0.5) & (serial["t_s"] < row.t_s + 0.5)]
        # the reading at the photo is the sensor's response to the held angle (noise ~ 40 ohm)
        assert abs(near["resistance_ohm"].median() - row.resistance_static_ohm) < 300


def test_same_seed_regenerates_bit_for_bit(tmp_path, experiment):
    write_experiment(tmp_path, trials=2, angles_deg=(0, 30, 60, 90), seed=11, shape=SMALL, show_progress=False)

    def digest(root):
        return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(root.rglob("*")) if p.is_file()}

    assert digest(tmp_path) == digest(experiment)


def test_pressure_simulation_reproduces_the_reference_fits():
    df = simulate_pressure(rng=0, repeats=50)
    assert list(df.columns) == ["mass_g", "trial", "angle_deg", "resistance_ohm"]
    p, _ = pressure_from_mass(df["mass_g"], reference.CONTACT_AREA_IN2)
    for y, ref in (("angle_deg", reference.ANGLE_VS_PRESSURE), ("resistance_ohm", reference.RESISTANCE_VS_PRESSURE)):
        coef, cov = np.polyfit(p, df[y], 1, cov=True)
        se = np.sqrt(np.diag(cov))
        assert abs(coef[0] - ref[0]) < 3 * se[0] and abs(coef[1] - ref[1]) < 3 * se[1]


def test_pressure_of_200_g_on_the_reference_pad():
    psi, kpa = pressure_from_mass(200.0, 0.05)
    assert psi == pytest.approx(8.818, abs=0.005)   # 1.961 N over 32.26 mm^2
    assert kpa == pytest.approx(60.80, abs=0.05)
    with pytest.raises(ValueError, match="contact_area_in2"):
        pressure_from_mass(20, 0)


def test_bad_plans():
    with pytest.raises(ValueError, match="angles_deg"):
        TrialPlan(angles_deg=())
    with pytest.raises(ValueError, match="angles_deg"):
        TrialPlan(angles_deg=(0, 200))
    with pytest.raises(ValueError, match="hold_s"):
        TrialPlan(hold_s=0)


def test_cli_render_writes_an_experiment_and_refuses_a_non_empty_folder(tmp_path, capsys):
    out = tmp_path / "exp"
    assert main(["render", "--out", str(out), "--trials", "1", "--angles", "0:20:10", "--size", "160x120",
                 "--seed", "3"]) == 0
    assert len(list((out / "trial_01" / "images").iterdir())) == 3
    capsys.readouterr()
    assert main(["render", "--out", str(out), "--trials", "1"]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "not empty" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("argv,word", [(["--angles", "0:x"], "--angles"), (["--size", "12"], "--size")])
def test_cli_render_bad_arguments(tmp_path, capsys, argv, word):
    with pytest.raises(SystemExit) as e:
        main(["render", "--out", str(tmp_path / "x")] + argv)
    assert e.value.code == 2
    assert word in capsys.readouterr().err
