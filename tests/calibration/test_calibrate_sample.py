"""End to end: the `calibrate` console script on the shipped sample, photos measured by vision."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SAMPLE = Path(__file__).resolve().parents[2] / "datasets" / "sample"


@pytest.mark.slow
def test_calibrate_script_on_the_sample(tmp_path):
    exe = shutil.which("calibrate", path=str(Path(sys.executable).parent))
    assert exe, "the calibrate console script is not installed beside this Python"
    out = tmp_path / "out"
    proc = subprocess.run([exe, "--trials", str(SAMPLE), "--pressure", str(SAMPLE / "pressure.csv"),
                           "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert f"report: {out / 'report.html'}" in proc.stdout
    data = json.loads((out / "calibration.json").read_text())
    val = {v["mapping"]: v for v in data["validation"]}
    assert val["empirical"]["validation"] == "leave-one-trial-out"
    assert 4.5 < val["factory"]["rmse_deg"] < 7.5
    assert val["empirical"]["rmse_deg"] < 1.5 and val["physical"]["rmse_deg"] < 1.5
    # every photo is accounted for: used, or excluded with a reason the report shows
    assert data["pairs"]["used"] + len(data["pairs"]["excluded"]) == 50
    html = (out / "report.html").read_text()
    for e in data["pairs"]["excluded"]:
        assert Path(e["image"]).name in html
    assert (out / "overlays" / "contact_sheet.png").is_file()
    assert len(list((out / "overlays").glob("*_overlay.jpg"))) == 50
