"""Line fits: NIST StRD certified values, and the errors-in-variables fit against known truth."""

import warnings

import numpy as np
import pytest

from flexcal.calibration.regression import ols, york

# NIST/ITL StRD, Norris (calibration of ozone monitors), Norris.dat: 36 observations
NORRIS_Y = [0.1, 338.8, 118.1, 888.0, 9.2, 228.1, 668.5, 998.5, 449.1, 778.9, 559.2, 0.3, 0.1, 778.1, 668.8, 339.3,
            448.9, 10.8, 557.7, 228.3, 998.0, 888.8, 119.6, 0.3, 0.6, 557.6, 339.3, 888.0, 998.5, 778.9, 10.2, 117.6,
            228.9, 668.4, 449.2, 0.2]
NORRIS_X = [0.2, 337.4, 118.2, 884.6, 10.1, 226.5, 666.3, 996.3, 448.6, 777.0, 558.2, 0.4, 0.6, 775.5, 666.9, 338.0,
            447.5, 11.6, 556.0, 228.1, 995.8, 887.6, 120.2, 0.3, 0.3, 556.8, 339.1, 887.2, 999.0, 779.0, 11.1, 118.3,
            229.2, 669.1, 448.9, 0.5]


def test_ols_reproduces_nist_norris_certified_values():
    f = ols(NORRIS_X, NORRIS_Y)
    assert f.slope == pytest.approx(1.00211681802045, rel=1e-12)
    assert f.intercept == pytest.approx(-0.262323073774029, rel=1e-11)
    assert f.slope_se == pytest.approx(0.429796848199937e-03, rel=1e-10)
    assert f.intercept_se == pytest.approx(0.232818234301152, rel=1e-10)
    assert np.sqrt(np.sum(f.residuals ** 2) / (f.n - 2)) == pytest.approx(0.884796396144373, rel=1e-10)
    assert f.r2 == pytest.approx(0.999993745883712, rel=1e-12)
    assert np.sum(f.residuals ** 2) == pytest.approx(26.6173985294224, rel=1e-10)


def test_york_recovers_a_line_where_ols_is_attenuated():
    rng = np.random.default_rng(7)
    true_x = rng.uniform(0, 10, 400)
    sx, sy = 1.5, 0.5
    x = true_x + rng.normal(0, sx, true_x.size)
    y = 3.0 * true_x + 2.0 + rng.normal(0, sy, true_x.size)
    f, o = york(x, y, sx, sy), ols(x, y)
    assert abs(f.slope - 3.0) < 3 * f.slope_se
    assert abs(f.intercept - 2.0) < 3 * f.intercept_se
    assert o.slope < 3.0 - 5 * o.slope_se   # regression dilution: OLS is biased low here


def test_york_matches_scipy_odr_while_scipy_has_it():
    odr = pytest.importorskip("scipy.odr")
    rng = np.random.default_rng(3)
    x = np.linspace(0, 90, 30) + rng.normal(0, 0.8, 30)
    y = 587.1 * np.linspace(0, 90, 30) + 34400 + rng.normal(0, 300, 30)
    sx, sy = rng.uniform(0.3, 1.2, 30), rng.uniform(100, 400, 30)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        out = odr.ODR(odr.RealData(x, y, sx=sx, sy=sy), odr.unilinear, beta0=[500.0, 30000.0]).run()
    f = york(x, y, sx, sy)
    assert f.slope == pytest.approx(out.beta[0], rel=1e-6)
    assert f.intercept == pytest.approx(out.beta[1], rel=1e-6)
    assert f.slope_se == pytest.approx(out.sd_beta[0], rel=1e-3)
    assert f.intercept_se == pytest.approx(out.sd_beta[1], rel=1e-3)


@pytest.mark.parametrize("x, y, match", [
    ([1, 2], [1, 2], "at least 3"),
    ([1, 1, 1], [1, 2, 3], "at least 3"),
    ([1, 2, np.nan], [1, 2, 3], "finite"),
    ([1, 2, 3], [1, 2], "one length"),
])
def test_bad_input(x, y, match):
    with pytest.raises(ValueError, match=match):
        ols(x, y)
