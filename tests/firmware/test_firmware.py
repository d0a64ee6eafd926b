"""The firmware: host unit tests of its C core, the real AVR build, and the build running in simavr."""

import math
import re
import subprocess
import time
import weakref

import numpy as np
import pytest
import serial

from flexcal.capture.protocol import HEADER, Comment, Header, Sample, parse_line
from flexcal.divider import Divider

from sim_glove import ELF, FIRMWARE, build, require_toolchain, simulated_glove


@pytest.fixture(scope="module")
def built():
    return build()


def test_core_unit_tests_pass_on_the_host():
    require_toolchain()
    proc = subprocess.run(["make", "-C", str(FIRMWARE), "test"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert re.search(r"\d+ checks, 0 failed", proc.stdout)


def test_core_resistance_is_the_convention_of_flexcal_divider():
    require_toolchain()
    subprocess.run(["make", "-C", str(FIRMWARE), "build/test_core"], check=True, capture_output=True)
    out = subprocess.run([str(FIRMWARE / "build" / "test_core"), "--table"], capture_output=True, text=True,
                         check=True).stdout.split()
    table = np.array(out, float).reshape(-1, 2)
    want = Divider(r_fixed_ohm=47000).resistance_from_adc(table[:, 0])
    assert np.array_equal(np.isnan(table[:, 1]), np.isnan(want))
    ok = np.isfinite(want)
    np.testing.assert_allclose(table[ok, 1], want[ok], rtol=2e-6)


def test_the_sketch_builds_for_the_uno_and_reports_its_size(built):
    assert ELF.is_file()
    assert "Program:" in built and "Data:" in built
    flash = int(re.search(r"Program:\s+(\d+) bytes", built).group(1))
    ram = int(re.search(r"Data:\s+(\d+) bytes", built).group(1))
    assert flash < 32256 and ram < 2048 * 0.5   # fits the Uno, with room for a calibration table and the stack


# A port's partial last line, until its next read. Keyed by the port object itself (weakly):
# keyed by id(), a closed port's leftover went to the next test's port when the id was reused.
_pending: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _read_lines(port, seconds):
    """Complete lines received within ``seconds`` (a partial last line waits for the next call)."""
    lines, t_end = [], time.monotonic() + seconds
    buf = _pending.pop(port, b"")
    while time.monotonic() < t_end:
        buf += port.read(512)
        *done, buf = buf.split(b"\n")
        lines += [(time.monotonic(), d.decode("ascii", "replace")) for d in done]
    _pending[port] = buf
    return lines


@pytest.mark.slow
def test_simulated_glove_streams_the_protocol(built, tmp_path):
    d = Divider()
    script = "0 45000\n2.6 60000\n4.0 open\n4.6 short\n5.2 52000\n"
    with simulated_glove(script, tmp_path) as pty, serial.Serial(pty, 115200, timeout=0.05) as port:
        lines = _read_lines(port, 6.5)
    raw = [text for _, text in lines]
    assert all(text.endswith("\r") for text in raw[:-1]), "lines end in \\r\\n"
    parsed = [parse_line(text) for text in raw]
    comments = [p.text for p in parsed if isinstance(p, Comment)]
    assert comments[0].startswith("flexcal-firmware ")
    assert Divider.from_banner(comments[1]) == d
    assert any(isinstance(p, Header) for p in parsed) and HEADER in raw[3]
    samples = [(t, p) for (t, _), p in zip(lines, parsed) if isinstance(p, Sample)]
    t_ms = np.array([s.t_ms for _, s in samples], float)
    r = np.array([s.resistance_ohm for _, s in samples])
    # the rate: 50 Hz within 2 % on the device's clock
    first = t_ms < 2500
    rate = (first.sum() - 1) / ((t_ms[first][-1] - t_ms[first][0]) / 1000)
    assert rate == pytest.approx(50.0, rel=0.02)
    # resistance within the divider's quantisation of the scripted value
    for lo_ms, hi_ms, true_r in ((200, 2500, 45000.0), (2800, 3900, 60000.0), (5400, 6200, 52000.0)):
        sel = r[(t_ms > lo_ms) & (t_ms < hi_ms)]
        assert sel.size > 20
        adc = np.floor(d.adc_from_resistance(true_r))
        step_lo, step_hi = d.resistance_from_adc(adc - 0.5), d.resistance_from_adc(adc + 0.5)
        assert np.all((sel >= step_lo) & (sel <= step_hi)), (true_r, sel[:5])
    # rails: a warning, and NaN resistance while there
    assert any(c.startswith("warning: sensor open") for c in comments)
    assert any(c.startswith("warning: sensor shorted") for c in comments)
    assert any(c == "sensor ok again" for c in comments)
    rail = r[(t_ms > 4100) & (t_ms < 5100)]
    assert rail.size > 20 and np.isnan(rail).all()
    # factory mapping on the angle
    s = samples[len(samples) // 5][1]
    assert s.angle_deg == pytest.approx((s.resistance_ohm - 31250) / 577.9, abs=0.01)


@pytest.mark.slow
def test_the_simulated_uno_starts_when_the_port_is_opened(built, tmp_path):
    """An Uno resets when its port is opened; the simulator waits for the open, so a late host still gets the banner."""
    with simulated_glove("0 45000\n", tmp_path) as pty:
        time.sleep(0.5)   # a slow host; the old simulator had streamed (and pyserial's open flushed) 25 lines by now
        with serial.Serial(pty, 115200, timeout=0.05) as port:
            lines = _read_lines(port, 0.5)
    texts = [t.strip() for _, t in lines]
    assert texts[0].startswith("# flexcal-firmware "), texts[:3]
    assert texts[3] == HEADER
    t_ms = [parse_line(t).t_ms for t in texts[4:]]
    assert t_ms[0] < 50   # the firmware's clock starts at the open


@pytest.mark.slow
def test_simulated_glove_answers_commands(built, tmp_path):
    with simulated_glove("0 45000\n", tmp_path) as pty, serial.Serial(pty, 115200, timeout=0.05) as port:
        _read_lines(port, 0.8)
        port.write(b"rate 20\n")
        lines = _read_lines(port, 1.6)
        # one command at a time, each after the last one's reply (the Uno buffers 64 received bytes)
        for cmd in (b"map linear 587.1 34400\n", b"info\n", b"x" * 80 + b"\n", b"bogus\n"):
            port.write(cmd)
            lines += _read_lines(port, 0.4)
    texts = [t.strip() for _, t in lines]
    assert "# ok rate_hz=20" in texts
    i = texts.index("# ok rate_hz=20")
    t_ms = [parse_line(t).t_ms for t in texts[i + 1:] if isinstance(parse_line(t), Sample)]
    gaps = np.diff(t_ms)[2:12]
    assert np.all(np.abs(gaps - 50) <= 1), gaps   # now 20 Hz
    assert "# ok mapping=linear slope_ohm_per_deg=587.100 offset_ohm=34400.0" in texts
    assert "# info rate_hz=20 mapping=linear slope_ohm_per_deg=587.100 offset_ohm=34400.0" in texts
    assert any(t.startswith("# error: command too long") for t in texts)
    assert "# error: unknown command; send 'help'" in texts
    after = [parse_line(t) for t in texts[texts.index("# info rate_hz=20 mapping=linear slope_ohm_per_deg=587.100 "
                                                     "offset_ohm=34400.0"):] if isinstance(parse_line(t), Sample)]
    assert after and all(math.isclose(s.angle_deg, (s.resistance_ohm - 34400) / 587.1, abs_tol=0.011)
                         for s in after)


@pytest.mark.slow
def test_sketch_uses_a_calibration_header(built, tmp_path):
    """calibrate's flexcal_calibration.h, dropped into the sketch, makes the glove report corrected angles."""
    import shutil

    from flexcal.calibration.export import header_text
    from flexcal.calibration.mapping import LinearMapping, PhysicalMapping

    phys = PhysicalMapping(555.0, 34_200.0, (-2.0, 95.0), pressure_k_ohm_per_psi=80.0)
    data = {"flexcal_version": "test", "created": "now", "recommended_mapping": "physical",
            "mappings": {"physical": phys.to_dict(), "empirical": LinearMapping(587.1, 34_400.0, (-2.0, 95.0)).to_dict()},
            "validation": []}
    sketch = tmp_path / "flexcal_glove"
    shutil.copytree(FIRMWARE / "flexcal_glove", sketch, ignore=shutil.ignore_patterns("build-*"))
    (sketch / "flexcal_calibration.h").write_text(header_text(data))
    proc = subprocess.run(["make", "-C", str(sketch)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    ram = int(re.search(r"Data:\s+(\d+) bytes", proc.stdout).group(1))
    assert ram < 2048 * 0.6, f"{ram} bytes of RAM with a calibration table leaves too little stack"
    elf = sketch / "build-uno" / "flexcal_glove_.elf"
    with simulated_glove("0 60000\n", tmp_path, elf=elf) as pty, serial.Serial(pty, 115200, timeout=0.05) as port:
        lines = _read_lines(port, 1.5)
    texts = [t.strip() for _, t in lines]
    assert "# info rate_hz=50 mapping=calibrated" in texts
    s = [parse_line(t) for t in texts if isinstance(parse_line(t), Sample)][-1]
    # the firmware's table interpolation agrees with flexcal's own inversion of the model
    assert s.angle_deg == pytest.approx(float(phys.angle_deg(s.resistance_ohm)), abs=0.05)
