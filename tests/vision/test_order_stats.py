"""The quick median and percentile give numpy's values exactly (the measurement's
answers must not move by a rounding)."""

import numpy as np
import pytest

from flexcal.vision.order_stats import median, percentile


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_median_and_percentile_equal_numpys(dtype):
    rng = np.random.default_rng(7)
    for _ in range(2000):
        n = int(rng.integers(1, 200))
        x = (rng.normal(size=n) * 50).astype(dtype)
        if rng.random() < 0.3:
            x = np.round(x)                  # ties
        q = float(rng.choice([0, 5, 10, 30, 50, 95, 100, rng.uniform(0, 100)]))
        assert median(x) == np.median(x)
        assert np.asarray(median(x)).dtype == np.median(x).dtype
        assert percentile(x, q) == np.percentile(x, q)
        assert np.asarray(percentile(x, q)).dtype == np.percentile(x, q).dtype


def test_the_input_is_left_as_it_was():
    x = np.array([5.0, 1.0, 4.0, 2.0, 3.0])
    median(x), percentile(x, 95)
    assert x.tolist() == [5.0, 1.0, 4.0, 2.0, 3.0]


def test_the_median_of_nothing_is_nan_as_numpys():
    assert np.isnan(median(np.array([])))
