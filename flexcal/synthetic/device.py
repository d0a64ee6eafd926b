"""A Python stand-in for the glove on a pseudo-terminal, for tests and benchmarks.

``FakeGlove`` speaks the firmware's protocol (banner, header, data lines at a fixed
rate, ``rate``/``info`` commands) on the slave side of a pty that pyserial opens like a
real port. The resistance follows a script of ``(t_s, resistance_ohm)`` steps through
the same divider and ADC as ``flexcal.synthetic.sensor``. Where the AVR toolchain is
installed, the real firmware in simavr (firmware/sim) plays this part instead.
"""

from __future__ import annotations

import os
import threading
import time
import tty

import numpy as np

from flexcal.capture.protocol import EOL, HEADER, format_sample
from flexcal.divider import Divider, factory_angle_deg
from flexcal.synthetic.sensor import DeviceClock, banner_lines


class FakeGlove:
    """The glove's serial stream on a pty.

    Parameters
    ----------
    script : sequence of (t_s, resistance_ohm)
        The sensor's resistance from each time on (seconds since ``start()``).
    rate_hz : float
    noise_ohm : float
        White noise on the resistance before the ADC.
    clock : DeviceClock
        The device's millis() relative to the host (boot offset, drift).
    garbage : bytes
        Sent once before the banner (line noise, a wrong-baud burst).
    samples : bool
        False: a device that sends its banner (and garbage) but never a sample.
    """

    def __init__(self, script=((0.0, 45_000.0),), *, rate_hz: float = 50.0, divider: Divider = Divider(),
                 noise_ohm: float = 0.0, clock: DeviceClock = DeviceClock(), seed: int = 0, garbage: bytes = b"",
                 oversample: int = 16, samples: bool = True):
        self.script = sorted((float(t), float(r)) for t, r in script)
        self.rate_hz, self.divider, self.noise_ohm = float(rate_hz), divider, noise_ohm
        self.clock, self.garbage, self.oversample = clock, garbage, oversample
        self.samples = samples
        self.rng = np.random.default_rng(seed)
        self.lines_sent = 0
        self._stop = threading.Event()
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        self.port = os.ttyname(self._slave)
        self._thread: threading.Thread | None = None
        self.t0 = None

    def resistance_at(self, t_s: float) -> float:
        r = self.script[0][1]
        for t, v in self.script:
            if t <= t_s:
                r = v
        return r

    def start(self, delay_s: float = 0.0) -> "FakeGlove":
        """Start streaming after ``delay_s`` (an Arduino boots when the host opens the port;
        pyserial discards what arrived before it opened)."""
        self.t0 = time.monotonic() + delay_s
        self._thread = threading.Thread(target=self._run, name="fake glove", daemon=True)
        self._thread.start()
        return self

    def _send(self, text: str) -> None:
        data = (text + EOL).encode()
        while data and not self._stop.is_set():
            try:
                n = os.write(self._master, data)
            except BlockingIOError:
                time.sleep(0.001)
                continue
            except OSError:
                return
            data = data[n:]

    def _commands(self, buf: bytearray) -> None:
        import select

        while select.select([self._master], [], [], 0)[0]:
            try:
                buf += os.read(self._master, 1024)
            except OSError:
                return
        while b"\n" in buf:
            i = buf.index(b"\n")
            cmd = buf[:i].decode("ascii", "replace").strip()
            del buf[: i + 1]
            if cmd.startswith("rate ") and cmd[5:].isdigit() and 1 <= int(cmd[5:]) <= 1000:
                self.rate_hz = float(cmd[5:])
                self._send(f"# ok rate_hz={cmd[5:]}")
            elif cmd == "info":
                self._send(f"# info rate_hz={self.rate_hz:g} mapping=factory")
            elif cmd:
                self._send("# error: unknown command; send 'help'")

    def _run(self):
        while time.monotonic() < self.t0 and not self._stop.is_set():
            time.sleep(0.005)
        if self.garbage:
            os.write(self._master, self.garbage)
        for line in banner_lines(self.divider, rate_hz=self.rate_hz):
            self._send(line)
        self._send(HEADER)
        cmd_buf, t_next = bytearray(), 0.0
        while not self._stop.is_set():
            now = time.monotonic() - self.t0
            if not self.samples:
                self._commands(cmd_buf)
                time.sleep(0.01)
                continue
            if now < t_next:
                time.sleep(min(0.002, t_next - now))
                continue
            self._commands(cmd_buf)
            chunk = []
            while t_next <= now:   # catch up in one write when the scheduler was late
                r = self.resistance_at(t_next) + (self.rng.normal(0, self.noise_ohm) if self.noise_ohm else 0.0)
                ideal = self.divider.adc_from_resistance(r)
                adc = float(self.divider.quantise(ideal + self.rng.normal(0, 0.5, self.oversample)).mean())
                res = float(self.divider.resistance_from_adc(adc))
                t_ms = int(self.clock.t_ms(t_next))
                chunk.append(format_sample(t_ms, adc, res, float(factory_angle_deg(res))))
                t_next += 1.0 / self.rate_hz
            for line in chunk:
                self._send(line)
            self.lines_sent += len(chunk)

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2)
        for fd in (self._master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()
