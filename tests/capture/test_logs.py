"""read_log on the dialects people really have, written to real files."""

import numpy as np
import pandas as pd
import pytest

from flexcal.capture.logs import read_log
from flexcal.divider import Divider
from flexcal.errors import FlexcalError
from flexcal.synthetic.sensor import simulate_readings, write_device_stream


def _write(tmp_path, text, name="log.txt", encoding="utf-8", newline="\n"):
    p = tmp_path / name
    with open(p, "w", encoding=encoding, newline="") as f:
        f.write(text.replace("\n", newline))
    return p


def test_reads_the_firmware_stream_with_banner(tmp_path):
    readings = simulate_readings(np.arange(0, 2, 0.02), np.linspace(0, 60, 100), rng=1)
    p = tmp_path / "stream.txt"
    write_device_stream(p, readings)
    df = read_log(p)
    assert len(df) == 100
    np.testing.assert_allclose(df["resistance_ohm"], readings["resistance_ohm"], atol=0.06)
    np.testing.assert_allclose(df["angle_deg"], readings["angle_deg"], atol=0.006)
    assert df["t_device_ms"].notna().all() and df["t_s"].iloc[0] == pytest.approx(df["t_device_ms"].iloc[0] / 1000)
    info = df.attrs["log"]
    assert info.divider == Divider() and info.divider_source == "firmware banner"
    assert info.bad_lines == 0 and info.angle_source == "firmware"


def test_reads_capture_serial_csv(tmp_path):
    text = ("t_s,t_host_s,t_device_ms,adc,resistance_ohm,angle_deg\n"
            "10.00,10.002,2000,432.94,34495.2,5.62\n10.02,10.021,2020,433.12,34521.1,5.66\n"
            "10.04,10.043,2040,433.6,34590.2,5.78\n")
    df = read_log(_write(tmp_path, text, "serial.csv"))
    assert list(df.columns[:7]) == ["t_s", "t_host_s", "t_device_ms", "adc", "resistance_ohm", "angle_deg", "line"]
    assert df["t_s"].tolist() == [10.0, 10.02, 10.04]
    assert df["line"].tolist() == [2, 3, 4]
    assert "t_s as written" in df.attrs["log"].time_source


def test_serial_monitor_paste(tmp_path):
    text = ("95.2 ohms\n"                       # partial first line
            "# Flex sensor test\n"
            "// starting...\n"
            "\n"
            "Resistance: 45010.5 ohms\n"
            "Resistance: 45100.0 ohms\n"
            "# calibrating...45200\n"          # value glued onto a comment line
            "Resistance: 45300.25 ohms\n"
            "Resistance: ohms garbage\n"
            "Resistance: 45400 ohms\n")
    df = read_log(_write(tmp_path, text, newline="\r\n"))
    assert df["resistance_ohm"].tolist() == [45010.5, 45100.0, 45200.0, 45300.25, 45400.0]
    info = df.attrs["log"]
    assert info.bad_lines == 2
    assert [n for n, _, _ in info.bad_examples] == [1, 9]
    assert df["t_s"].isna().all() and "row order" in info.time_source
    # no firmware angle in the log: the factory mapping, and the report says so
    np.testing.assert_allclose(df["angle_deg"], (df["resistance_ohm"] - 31250) / 577.9)
    assert "factory" in info.angle_source


@pytest.mark.parametrize("sep", [";", "\t"])
def test_other_separators_trailing_separator_bom_and_kohm_mojibake(tmp_path, sep):
    rows = ["time_ms{0}Resistance (kÎ©){0}Angle{0}".format(sep)]
    for i in range(6):
        rows.append(f"{1000 + 20 * i}{sep}{45 + 0.1 * i:.1f}{sep}{23.4 + i:.1f}{sep}")
    p = _write(tmp_path, "\ufeff" + "\n".join(rows) + "\n", "log.csv", newline="\r\n")
    df = read_log(p)
    np.testing.assert_allclose(df["resistance_ohm"], [45000 + 100 * i for i in range(6)])
    np.testing.assert_allclose(df["t_s"], [1.0 + 0.02 * i for i in range(6)])
    assert df["angle_deg"].iloc[0] == pytest.approx(23.4)
    assert "kΩ" in df.attrs["log"].resistance_unit and "unit" in df.attrs["log"].resistance_unit


def test_headerless_kohm_by_magnitude(tmp_path):
    text = "".join(f"{0.5 * i:.2f},{44.25 + i:.2f}\n" for i in range(10))
    df = read_log(_write(tmp_path, text, "log.csv"))
    np.testing.assert_allclose(df["resistance_ohm"], [44_250 + 1000 * i for i in range(10)])
    np.testing.assert_allclose(df["t_s"], 0.5 * np.arange(10))
    assert "magnitude" in df.attrs["log"].resistance_unit


def test_adc_only_needs_a_divider(tmp_path):
    text = "ms,adc\n" + "".join(f"{100 * i},{500 + i}\n" for i in range(10))
    p = _write(tmp_path, text, "adc.csv")
    with pytest.raises(FlexcalError, match="r-fixed-ohm"):
        read_log(p)
    d = Divider(r_fixed_ohm=10_000)
    df = read_log(p, divider=d)
    np.testing.assert_allclose(df["resistance_ohm"], d.resistance_from_adc(np.arange(500, 510)))
    assert "computed from ADC" in df.attrs["log"].resistance_unit


def test_adc_only_with_banner_divider(tmp_path):
    text = ("# divider: r_fixed_ohm=22000 vref_v=3.3 adc_bits=10 flex=low-side\n"
            + "".join(f"{600 + i}\n" for i in range(10)))
    df = read_log(_write(tmp_path, text))
    np.testing.assert_allclose(df["resistance_ohm"], Divider(22_000, 3.3).resistance_from_adc(np.arange(600, 610)))


def test_host_time_only_and_time_going_backwards(tmp_path):
    text = "host_time,resistance\n1.0,45000\n1.1,45010\n0.2,45020\n0.3,45030\n0.4,45040\n"
    df = read_log(_write(tmp_path, text, "log.csv"))
    assert df["t_s"].tolist() == [1.0, 1.1, 0.2, 0.3, 0.4]
    assert any("backwards" in n and "line 4" in n for n in df.attrs["log"].notes)


@pytest.mark.parametrize("text, match", [
    ("", "no data lines"),
    ("# only a comment\n\n", "no data lines"),
    ("hello world\nfoo bar baz\nqux\n", "no"),
])
def test_no_usable_data_is_one_line_error(tmp_path, text, match):
    with pytest.raises(FlexcalError, match=match) as e:
        read_log(_write(tmp_path, text))
    assert "\n" not in str(e.value) and "log.txt" in str(e.value)


def test_missing_file(tmp_path):
    with pytest.raises(FlexcalError, match="no such log file"):
        read_log(tmp_path / "nope.csv")


def test_latin1_file_and_unknown_columns_kept(tmp_path):
    p = tmp_path / "log.csv"
    p.write_bytes("t_ms,R (ohm),temp °C\n0,45000,21.5\n20,45010,21.6\n".encode("latin-1"))
    df = read_log(p)
    assert df["resistance_ohm"].tolist() == [45000, 45010]
    assert df["temp °C"].tolist() == [21.5, 21.6]
    assert isinstance(df, pd.DataFrame)
