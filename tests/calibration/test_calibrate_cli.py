"""flexcal calibrate and flexcal apply on a simulated experiment, through the real CLI and files."""

import json
import shutil
import subprocess

import numpy as np
import pandas as pd
import pytest

from flexcal.calibration.export import load
from flexcal.cli import main
from flexcal.errors import FlexcalError


@pytest.fixture(scope="module")
def calibrated(experiment, tmp_path_factory):
    out = tmp_path_factory.mktemp("cal")
    rc = main(["calibrate", "--trials", str(experiment), "--angles", str(experiment / "angles.csv"),
               "--pressure", str(experiment / "pressure.csv"), "--out", str(out)])
    assert rc == 0
    return out


def test_outputs_are_written(calibrated, capsys):
    for name in ("pairs.csv", "calibration.json", "report.html", "flexcal_calibration.h"):
        assert (calibrated / name).stat().st_size > 0, name
    figs = sorted(p.name for p in (calibrated / "figures").glob("*.png"))
    for key in ("fig06", "fig07", "fig08", "fig11", "fig12", "fig13", "fig14", "residuals", "validation"):
        assert any(f.startswith(key) for f in figs), key
    pairs = pd.read_csv(calibrated / "pairs.csv")
    assert {"trial", "image", "t_s", "angle_actual_deg", "angle_actual_unc_deg", "resistance_ohm",
            "resistance_std_ohm", "n_samples", "angle_measured_deg", "steady", "used", "excluded"} <= set(pairs.columns)
    assert len(pairs) == 50 and pairs["used"].all()


def test_report_is_self_contained_with_reference_numbers(calibrated):
    html = (calibrated / "report.html").read_text()
    assert html.count('src="data:image/png;base64,') >= 9
    assert "src=\"http" not in html and "href=\"http" not in html
    for ref in ("R = 587.1 θ + 34400 Ω", "R = 577.9 θ + 31250 Ω", "R_err = 9.2 θ + 3150 Ω", "leave-one-trial-out"):
        assert ref in html, ref


def test_calibration_json_provenance_and_load(calibrated, experiment):
    data = json.loads((calibrated / "calibration.json").read_text())
    assert data["schema_version"] == 1 and data["flexcal_version"]
    t = data["inputs"]["trials"][0]
    assert len(t["log_sha256"]) == 64 and len(t["images"]) == 10 and len(t["images"][0]["sha256"]) == 64
    eq17 = data["models"]["eq17_resistance_vs_photo_angle"]
    assert {"slope", "intercept", "slope_se", "intercept_se", "covariance", "r2", "rmse"} <= set(eq17)
    cal = load(calibrated / "calibration.json")
    m = cal.mapping("empirical")
    r = m.resistance_ohm(np.array([10.0, 45.0, 80.0]))
    np.testing.assert_allclose(cal.angle_deg(r, mapping="empirical"), [10, 45, 80], atol=1e-9)
    p = cal.mapping("physical")
    np.testing.assert_allclose(p.angle_deg(p.resistance_ohm(np.array([5.0, 50.0, 85.0]))), [5, 50, 85], atol=0.01)
    assert data["recommended_mapping"] in ("empirical", "physical")


def test_load_rejects_other_files(tmp_path):
    (tmp_path / "x.json").write_text('{"a": 1}')
    with pytest.raises(FlexcalError, match="not a flexcal calibration"):
        load(tmp_path / "x.json")
    (tmp_path / "y.json").write_text("{")
    with pytest.raises(FlexcalError, match="not a JSON file"):
        load(tmp_path / "y.json")


def test_firmware_header_compiles_and_matches(calibrated, tmp_path):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler on this machine")
    cal = load(calibrated / "calibration.json")
    m = cal.mapping()
    lo, hi = m.resistance_range_ohm
    rs = np.linspace(lo, hi, 57)
    src = tmp_path / "t.c"
    src.write_text('#include <stdio.h>\n#include "flexcal_calibration.h"\nint main(void){float r;'
                   'while (scanf("%f", &r) == 1) printf("%.6f\\n", flexcal_cal_angle_deg(r));return 0;}\n')
    exe = tmp_path / "t"
    subprocess.run([cc, "-std=c99", "-Wall", "-Werror", "-I", str(calibrated), str(src), "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], input="\n".join(f"{r:.3f}" for r in rs), capture_output=True, text=True,
                         check=True).stdout.split()
    np.testing.assert_allclose(np.array(out, float), m.angle_deg(rs), atol=0.05)


def test_apply_adds_corrected_angles_and_refuses_out_of_range(calibrated, experiment, tmp_path, capsys):
    log = experiment / "trial_03" / "serial.csv"
    cal = calibrated / "calibration.json"
    out = tmp_path / "corrected.csv"
    s = pd.read_csv(log)
    lo, hi = load(cal).mapping().resistance_range_ohm
    inside = s[(s["resistance_ohm"] >= lo) & (s["resistance_ohm"] <= hi)]
    inside.to_csv(tmp_path / "inside.csv", index=False)
    assert main(["apply", "--calibration", str(cal), "--log", str(tmp_path / "inside.csv"), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert {"angle_corrected_deg", "angle_empirical_deg", "angle_physical_deg", "angle_factory_deg"} <= set(df.columns)
    # on the held photos the corrected angle is the true one, the factory's is ~6 deg high
    truth = pd.read_csv(experiment / "trial_03" / "truth.csv")
    t = np.interp(truth["t_s"], df["t_s"], df["angle_corrected_deg"])
    f = np.interp(truth["t_s"], df["t_s"], df["angle_factory_deg"])
    ok = (truth["angle_deg"] > 3) & (truth["angle_deg"] < 87)
    assert np.abs(t - truth["angle_deg"])[ok].max() < 1.5
    assert np.mean(f - truth["angle_deg"]) > 4.5
    # the full log has readings beyond the calibrated range: refused, one line, then --extrapolate
    s.loc[len(s)] = s.iloc[-1]
    s.loc[len(s) - 1, "resistance_ohm"] = hi + 5_000
    s.to_csv(tmp_path / "beyond.csv", index=False)
    assert main(["apply", "--calibration", str(cal), "--log", str(tmp_path / "beyond.csv"), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "outside the calibrated range" in err and "--extrapolate" in err and "\n" not in err
    assert main(["apply", "--calibration", str(cal), "--log", str(tmp_path / "beyond.csv"), "--out", str(out),
                 "--extrapolate"]) == 0
    assert pd.read_csv(out)["extrapolated"].iloc[-1]


@pytest.mark.parametrize("args, match", [
    (["--images", "nowhere"], "say where"),
    (["--images", "nowhere", "--log", "x.csv"], "--images nowhere: no such"),
    (["--trials", "nowhere"], "--trials nowhere: no such"),
])
def test_bad_arguments_get_one_line(args, match, capsys, tmp_path):
    assert main(["calibrate", *args, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert match in err and "\n" not in err


def test_mismatched_images_and_logs(experiment, tmp_path, capsys):
    rc = main(["calibrate", "--images", str(experiment / "trial_01" / "images"), str(experiment / "trial_02" / "images"),
               "--log", str(experiment / "trial_01" / "serial.csv"), "--out", str(tmp_path / "o")])
    assert rc == 2 and "2 --images folder(s) but 1 --log" in capsys.readouterr().err


def test_a_broken_trial_is_left_out_and_the_rest_carries_on(experiment, tmp_path, capsys):
    exp = tmp_path / "exp"
    for t in ("trial_01", "trial_02", "trial_03"):
        shutil.copytree(experiment / t, exp / t)
    (exp / "trial_02" / "serial.csv").write_text("# the glove was unplugged\n")
    out = tmp_path / "out"
    assert main(["calibrate", "--trials", str(exp), "--angles", str(experiment / "angles.csv"), "--out", str(out)]) == 0
    data = json.loads((out / "calibration.json").read_text())
    assert data["pairs"] == {**data["pairs"], "total": 30, "used": 20}
    reasons = {e["reason"] for e in data["pairs"]["excluded"]}
    assert len(reasons) == 1 and reasons.pop().startswith("trial not paired: ")
    assert any("trial trial_02 left out" in n and "no data lines" in n for n in data["notes"])
    assert data["inputs"]["trials"][1]["log_reading"] is None
    assert len(pd.read_csv(out / "pairs.csv")) == 30
    steps = pd.read_csv(out / "steps.csv")
    assert len(steps) == 10 and (steps["n"] == 2).all()
