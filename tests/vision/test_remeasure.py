"""flexcal remeasure: a rendered trial re-measured and compared with ImageJ-style references."""

import json

import numpy as np
import pandas as pd
import pytest

from flexcal.cli import main
from flexcal.errors import FlexcalError
from flexcal.remeasure import bland_altman, map_reference
from flexcal.synthetic.trial import TrialPlan, simulate_trial


@pytest.fixture(scope="module")
def trial(tmp_path_factory):
    d = tmp_path_factory.mktemp("old") / "trial_01"
    simulate_trial(d, plan=TrialPlan(angles_deg=(5, 25, 45, 65, 85)), difficulty="clean", rng=5, shape=(480, 640))
    return d


def _imagej(truth, rng, repeats=1, label=True):
    rows = []
    for _, r in truth.iterrows():
        for _ in range(repeats):
            row = {" ": len(rows) + 1}
            if label:
                row["Label"] = r.image
            row["Angle"] = 180.0 - (r.angle_deg + rng.normal(0, 1.0))   # interior, a few tenths of human error
            rows.append(row)
    return pd.DataFrame(rows)


def test_remeasure_against_an_imagej_table_with_labels_and_repeats(trial, tmp_path, capsys):
    truth = pd.read_csv(trial / "truth.csv")
    ref = _imagej(truth, np.random.default_rng(1), repeats=3).sample(frac=1, random_state=3)   # any row order
    ref.to_csv(tmp_path / "Results.csv", index=False)
    out = tmp_path / "out"
    assert main(["remeasure", str(trial), "--reference", str(tmp_path / "Results.csv"), "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert "15 reference rows mapped to 5 photos by Label" == s["mapping"]
    comp = pd.read_csv(out / "comparison.csv")
    assert (comp["reference_n"] == 3).all()
    # worst first, and the statistics are those of the differences in the table
    d = comp["difference_deg"].dropna()
    assert list(d.abs()) == sorted(d.abs(), reverse=True)
    assert s["bland_altman"]["bias_deg"] == pytest.approx(d.mean(), abs=1e-3)
    assert s["bland_altman"]["loa_high_deg"] == pytest.approx(d.mean() + 1.96 * d.std(), abs=1e-3)
    # the reference is the truth within its averaged noise; flexcal on clean renders agrees with it
    merged = comp.assign(name=comp["image"].map(lambda p: p.split("/")[-1])).merge(truth, left_on="name",
                                                                                     right_on="image")
    assert np.abs(merged["reference_deg"] - merged["angle_deg_y"]).max() < 2.5
    assert s["bland_altman"]["n"] >= 4 and abs(s["bland_altman"]["bias_deg"]) < 2.0
    for f in ("angles.csv", "bland_altman.png", "worst.png", "overlays/contact_sheet.png"):
        assert (out / f).is_file(), f
    said = capsys.readouterr().out
    assert "limits of agreement" in said
    # every photo measured sure: none listed as not measured or with a doubt
    assert (pd.read_csv(out / "angles.csv")["status"] == "ok").all() and "not measured" not in said


def test_rows_without_labels_map_in_sorted_order(trial, tmp_path):
    truth = pd.read_csv(trial / "truth.csv")
    images = sorted((trial / "images").iterdir())
    ref = pd.DataFrame({"image": None, "angle_deg": truth["angle_deg"]})
    mapped, how = map_reference(ref, images, "ref.csv")
    assert "sorted order" in how
    np.testing.assert_allclose(mapped["reference_deg"], truth.sort_values("image")["angle_deg"])
    with pytest.raises(FlexcalError, match="4 row.*5 photo.*counts must match"):
        map_reference(ref.iloc[:4], images, "ref.csv")


def test_unknown_label_is_named(trial):
    images = sorted((trial / "images").iterdir())
    ref = pd.DataFrame({"image": ["nope.jpg"], "angle_deg": [10.0]})
    with pytest.raises(FlexcalError, match="nope.jpg match no photo"):
        map_reference(ref, images, "ref.csv")


def test_bland_altman_known_values():
    ba = bland_altman([1.0, 2.0, 3.0, 4.0])
    assert ba["bias_deg"] == 2.5
    assert ba["sd_deg"] == pytest.approx(np.std([1, 2, 3, 4], ddof=1))
    assert ba["loa_low_deg"] == pytest.approx(2.5 - 1.96 * ba["sd_deg"])
