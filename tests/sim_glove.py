"""Build the firmware and run it in simavr behind a pseudo-terminal, for the tests.

Without the AVR toolchain and simavr the tests are skipped with a message naming the
Debian packages; in CI (CI=true) they fail instead, so that CI never silently skips them.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path

import pytest

FIRMWARE = Path(__file__).resolve().parents[1] / "firmware"
ELF = FIRMWARE / "flexcal_glove" / "build-uno" / "flexcal_glove_.elf"
SIM = FIRMWARE / "build" / "flexcal_sim"
PACKAGES = "gcc-avr avr-libc arduino-core-avr arduino-mk simavr libsimavr-dev libelf-dev pkg-config"


def missing_tools() -> list[str]:
    missing = [t for t in ("avr-gcc", "make", "cc", "pkg-config") if shutil.which(t) is None]
    if not Path("/usr/share/arduino/Arduino.mk").is_file():
        missing.append("arduino-mk")
    if shutil.which("pkg-config") and subprocess.run(["pkg-config", "--exists", "simavr"]).returncode:
        missing.append("libsimavr-dev")
    return missing


def require_toolchain():
    missing = missing_tools()
    if missing:
        msg = f"firmware toolchain missing ({', '.join(missing)}); apt-get install {PACKAGES}"
        if os.environ.get("CI") == "true":
            pytest.fail(msg)
        pytest.skip(msg)


def build() -> None:
    """make -C firmware (sketch for the Uno + simulator harness); raises with its output on failure."""
    require_toolchain()
    proc = subprocess.run(["make", "-C", str(FIRMWARE)], capture_output=True, text=True)
    if proc.returncode:
        raise AssertionError(f"make -C firmware failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc.stdout


@contextmanager
def simulated_glove(script: str, tmp_path: Path, *, r_fixed_ohm: float = 47000.0, duration_s: float | None = None,
                    elf: Path = ELF):
    """Run the firmware with a resistance script ("t_s resistance_ohm" lines); yields the pty path.

    The firmware starts when the port is opened (as an Uno resets then), so script times
    count from the open.
    """
    path = tmp_path / "script.txt"
    path.write_text(script)
    cmd = [str(SIM), str(elf), str(path), "--r-fixed-ohm", str(r_fixed_ohm)]
    if duration_s is not None:
        cmd += ["--duration", str(duration_s)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        pty = None
        deadline = time.monotonic() + 10
        while pty is None and time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            if line.startswith("pty "):
                pty = line.split()[1]
        if pty is None:
            raise AssertionError(f"the simulator did not start: {proc.stderr.read()}")
        yield pty
    finally:
        proc.kill()
        proc.wait(timeout=10)
        proc.stdout.close()
        proc.stderr.close()
