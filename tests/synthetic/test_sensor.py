import numpy as np
import pytest

from flexcal.calibration import reference
from flexcal.capture.protocol import Comment, Header, Sample, parse_line
from flexcal.divider import Divider, factory_angle_deg
from flexcal.synthetic.sensor import DeviceClock, SensorModel, device_lines, simulate_readings, write_device_stream


def test_static_response_reproduces_the_reference_fit_on_the_step_grid():
    grid = np.arange(0, 91, 10.0)
    slope, offset = np.polyfit(grid, SensorModel().resistance_ohm(grid), 1)
    assert slope == pytest.approx(reference.EQ17[0], abs=1e-6)
    assert offset == pytest.approx(reference.EQ17[1], abs=1e-3)


def test_factory_angle_overstates_the_true_angle_by_several_degrees():
    grid = np.arange(0, 91, 10.0)
    over = factory_angle_deg(SensorModel().resistance_ohm(grid)) - grid
    assert np.all(over > 4) and np.all(over < 8)


def test_noise_free_readings_match_the_model_within_adc_quantisation():
    div = Divider()
    model = SensorModel(noise_ohm=0, adc_noise_lsb=0, tau_s=0)
    t = np.arange(0, 2, 0.02)
    angle = np.linspace(0, 90, len(t))
    df = simulate_readings(t, angle, model=model, divider=div, rng=0)
    r = model.resistance_ohm(angle)
    step = div.resistance_from_adc(div.adc_from_resistance(r) + 1) - r  # one LSB in ohm
    assert np.all(np.abs(df["resistance_ohm"] - r) <= step)
    np.testing.assert_allclose(df["angle_deg"], factory_angle_deg(df["resistance_ohm"]))


def test_oversampling_with_dither_resolves_below_one_lsb():
    div = Divider()
    t = np.arange(0, 20, 0.02)
    df = simulate_readings(t, np.full_like(t, 45.0), model=SensorModel(noise_ohm=0, tau_s=0), divider=div, rng=1)
    r = SensorModel().resistance_ohm(45.0)
    lsb = div.resistance_from_adc(div.adc_from_resistance(r) + 1) - r
    assert abs(df["resistance_ohm"].mean() - r) < 0.15 * lsb


def test_settling_after_a_step_follows_the_time_constant():
    tau = 0.5
    model = SensorModel(noise_ohm=0, adc_noise_lsb=0, tau_s=tau)
    t = np.arange(0, 5, 0.01)
    angle = np.where(t < 1, 0.0, 60.0)
    df = simulate_readings(t, angle, model=model, rng=0)
    r0, r1 = model.resistance_ohm(0), model.resistance_ohm(60)
    i = np.searchsorted(t, 1 + tau - 1e-9)
    frac = (df["resistance_true_ohm"].iloc[i] - r0) / (r1 - r0)
    assert frac == pytest.approx(1 - np.exp(-1), abs=0.03)
    left = r1 - df["resistance_true_ohm"].iloc[-1]
    assert left == pytest.approx((r1 - r0) * np.exp(-(t[-1] - 1) / tau), rel=0.05)


def test_hysteresis_and_drift():
    h = 800.0
    model = SensorModel(noise_ohm=0, adc_noise_lsb=0, tau_s=0, hysteresis_ohm=h)
    t = np.arange(0, 6, 0.02)
    angle = np.interp(t, [0, 2, 3, 5, 6], [0, 45, 45, 0, 0])
    up = np.interp(1.0, [0, 2], [0, 45])
    df = simulate_readings(t, angle, model=model, rng=0)
    r_up = df["resistance_true_ohm"][np.isclose(t, 1.0)].iloc[0]
    r_down = df["resistance_true_ohm"][np.isclose(t, 4.0)].iloc[0]  # same angle on the way down
    assert r_up - r_down == pytest.approx(h, abs=1e-6)
    assert r_up == pytest.approx(model.resistance_ohm(up) + h / 2)
    drift = simulate_readings(t, angle, model=SensorModel(noise_ohm=0, tau_s=0, drift_ohm_per_s=10.0), rng=0)
    np.testing.assert_allclose(
        drift["resistance_true_ohm"] - SensorModel().resistance_ohm(angle), 10.0 * t, atol=1e-6)


def test_device_stream_parses_back_to_the_same_numbers(tmp_path):
    t = np.arange(0, 3, 0.02)
    df = simulate_readings(t, 30 + 20 * np.sin(t), rng=3)
    clock = DeviceClock(boot_ms=1234, drift_ppm=50)
    path = tmp_path / "stream.txt"
    write_device_stream(path, df, clock=clock)
    raw = path.read_bytes()
    assert raw.count(b"\r\n") == raw.count(b"\n") and raw.endswith(b"\r\n")
    parsed = [parse_line(line) for line in raw.decode().split("\r\n") if line]
    comments = [p for p in parsed if isinstance(p, Comment)]
    assert any("flexcal-firmware" in c.text for c in comments)
    assert Divider.from_banner(" ".join(c.text for c in comments)) == Divider()
    assert sum(isinstance(p, Header) for p in parsed) == 1
    samples = [p for p in parsed if isinstance(p, Sample)]
    assert len(samples) == len(df)
    np.testing.assert_array_equal([s.t_ms for s in samples], clock.t_ms(t))
    np.testing.assert_allclose([s.adc for s in samples], df["adc"], atol=0.005 + 1e-9)
    np.testing.assert_allclose([s.resistance_ohm for s in samples], df["resistance_ohm"], atol=0.05 + 1e-9)
    np.testing.assert_allclose([s.angle_deg for s in samples], df["angle_deg"], atol=0.005 + 1e-9)
    assert list(device_lines(df.iloc[:1], banner=False))[0].count(",") == 3


@pytest.mark.parametrize("kwargs,name", [
    (dict(noise_ohm=-1), "noise_ohm"), (dict(tau_s=-0.1), "tau_s"), (dict(hysteresis_ohm=-5), "hysteresis_ohm"),
])
def test_bad_sensor_parameters(kwargs, name):
    with pytest.raises(ValueError, match=name):
        SensorModel(**kwargs)


def test_bad_series_and_divider():
    with pytest.raises(ValueError, match="t_s"):
        simulate_readings([0, 1, 1], [0, 0, 0])
    with pytest.raises(ValueError, match="oversample"):
        simulate_readings([0, 1], [0, 0], oversample=0)
    with pytest.raises(ValueError, match="r_fixed_ohm"):
        Divider(r_fixed_ohm=-10)


def test_divider_round_trip_and_rails():
    div = Divider(r_fixed_ohm=22_000, adc_bits=12)
    r = np.array([5_000.0, 22_000.0, 90_000.0])
    back = div.resistance_from_adc(div.quantise(div.adc_from_resistance(r)))
    lsb = div.resistance_from_adc(div.adc_from_resistance(r) + 1) - r
    assert np.all(np.abs(back - r) <= lsb)
    assert np.isnan(div.resistance_from_adc([0, div.full_scale - 1])).all()
