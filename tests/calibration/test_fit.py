"""Known answers: an experiment simulated with the reference's parameters gives back its fits."""

import numpy as np
import pandas as pd
import pytest

from flexcal.calibration import reference
from flexcal.calibration.experiment import build_pairs, find_trials, read_angles
from flexcal.calibration.fit import fit_calibration, fit_pressure, select_pairs
from flexcal.errors import FlexcalError


@pytest.fixture(scope="module")
def pairs(experiment):
    p, _, _, _ = build_pairs(find_trials([experiment]), angles=read_angles(experiment / "angles.csv"),
                             progress=False)
    return p


@pytest.fixture(scope="module")
def result(pairs, experiment):
    return fit_calibration(pairs, pressure=fit_pressure(pd.read_csv(experiment / "pressure.csv")))


def _within(value, se, ref, k=2.0):
    assert abs(value - ref) <= k * se, f"{value:.4g} ± {se:.2g} is not within {k} SE of {ref}"


def test_recovers_eq16_to_eq18(result):
    r = result
    assert r.used.shape[0] == 50
    _within(r.eq16.slope, r.eq16.slope_se, reference.EQ16[0])
    _within(r.eq16.intercept, r.eq16.intercept_se, reference.EQ16[1])
    _within(r.eq17.slope, r.eq17.slope_se, reference.EQ17[0])
    _within(r.eq17.intercept, r.eq17.intercept_se, reference.EQ17[1])
    _within(r.eq18["slope"], r.eq18["slope_se"], reference.EQ18[0])
    _within(r.eq18["intercept"], r.eq18["intercept_se"], reference.EQ18[1])
    # the direct fit of the per-photo error is the same line as the difference of the fits (OLS)
    assert r.eq18_direct.slope == pytest.approx(r.eq17_ols.slope - r.eq16.slope, abs=1e-6)


def test_recovers_the_pressure_experiment_and_eq19(result):
    p = result.pressure
    _within(p.angle_fit.slope, p.angle_fit.slope_se, reference.ANGLE_VS_PRESSURE[0])
    _within(p.angle_fit.intercept, p.angle_fit.intercept_se, reference.ANGLE_VS_PRESSURE[1])
    _within(p.resistance_fit.slope, p.resistance_fit.slope_se, reference.RESISTANCE_VS_PRESSURE[0])
    _within(p.resistance_fit.intercept, p.resistance_fit.intercept_se, reference.RESISTANCE_VS_PRESSURE[1])
    _within(p.ratio_ohm_per_deg, p.ratio_se, reference.EQ19_SLOPE)


def test_physical_model_recovers_the_simulated_sensor(result):
    from flexcal.synthetic.sensor import SensorModel

    s, f = SensorModel(), result.physical_fit
    _within(f["pressure_k_ohm_per_psi"], f["pressure_k_se"], s.pressure_k_ohm_per_psi)
    _within(f["slope_ohm_per_deg"], f["slope_se"], s.slope_ohm_per_deg)
    _within(f["offset_ohm"], f["offset_se"], s.offset_ohm)
    # the reference's form (eq 16 line + pressure term) removes about half of the error
    assert 0.3 < result.reference_model["share_of_error_removed"] < 0.8


def test_corrected_angle_at_the_noise_floor_factory_about_six_degrees(result):
    v = result.validation.set_index("mapping")
    assert (v["validation"].drop("factory") == "leave-one-trial-out").all()
    assert 5.0 < v.loc["factory", "rmse_deg"] < 7.5
    for name in ("empirical", "physical"):
        # photo angles carry 0.5 deg of noise: that is the floor
        assert v.loc[name, "rmse_deg"] < 0.8
        assert abs(v.loc[name, "bias_deg"]) < 0.3


def test_bad_photos_are_excluded_and_listed(pairs):
    p = pairs.copy()
    p.loc[3, "angle_actual_deg"] += 15.0                      # a confident vision mistake
    p.loc[7, ["angle_actual_deg", "status", "reason"]] = [np.nan, "failed", "no finger found"]
    p.loc[12, "status"] = "low_confidence"
    p.loc[20, "steady"] = False
    s = select_pairs(p)
    assert s["excluded"].iloc[3].startswith("photo angle +15.")
    assert s["excluded"].iloc[7] == "no photo angle: no finger found"
    assert s["excluded"].iloc[12].startswith("photo angle has low confidence")
    assert s["excluded"].iloc[20] == "signal not steady around the photo"
    assert s["used"].sum() == len(p) - 4
    assert list(pairs.columns) == list(p.columns)   # the caller's table is left alone


def test_single_trial_says_it_cannot_cross_validate(pairs):
    r = fit_calibration(pairs[pairs["trial"] == "trial_02"])
    assert any("only one trial" in n for n in r.notes)
    assert r.validation.set_index("mapping").loc["empirical", "validation"].startswith("in-sample")


def test_too_few_pairs_is_a_clear_error(pairs):
    few = pairs.iloc[:6].assign(angle_actual_deg=[0, 10, 20, np.nan, np.nan, np.nan])
    with pytest.raises(FlexcalError, match=r"only 3 usable pair\(s\) of 6 \(excluded: 3 x no photo angle\).*at least 4"):
        fit_calibration(few)
    with pytest.raises(FlexcalError, match="only 0 usable"):
        fit_calibration(pairs.assign(angle_actual_deg=np.nan))
