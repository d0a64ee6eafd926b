"""Reading a serial device on a background thread, every line stamped on arrival.

``SerialReader(url)`` opens a port path or any pyserial URL (``loop://``,
``socket://host:port``, ``spy://...``) and puts ``Line`` (host monotonic time, text) and
``Event`` (disconnected, reconnected, overlong) items on a queue. Memory is bounded: a
device that sends bytes without newlines has its partial line dropped past
``max_line`` bytes (an ``overlong`` event says so).
"""

from __future__ import annotations

import queue
import threading
import time
from dataclasses import dataclass

import serial

from flexcal.capture.protocol import BAUD
from flexcal.errors import FlexcalError


@dataclass(frozen=True)
class Line:
    """One line as received: host monotonic time (s) when its last byte arrived, and its text."""

    t_host_s: float
    text: str


@dataclass(frozen=True)
class Event:
    """Something that happened to the connection: kind is disconnected, reconnected or overlong."""

    t_host_s: float
    kind: str
    detail: str = ""


def open_port(url: str, baud: int = BAUD, timeout: float = 0.05):
    """Open a port path or pyserial URL; a one-line FlexcalError naming it when that fails."""
    try:
        return serial.serial_for_url(url, baudrate=baud, timeout=timeout)
    except serial.SerialException as e:
        text = str(e)
        if "No such file" in text or "could not open port" in text and "Errno 2" in text:
            hint = "no such port; is the glove plugged in? (python -m serial.tools.list_ports lists ports)"
        elif "Permission denied" in text or "Errno 13" in text:
            hint = "permission denied; add yourself to the dialout group, or check no other program has it open"
        elif "busy" in text.lower() or "Errno 16" in text:
            hint = "the port is busy; close the Serial Monitor or any other program using it"
        else:
            hint = text
        raise FlexcalError(f"--port {url}: {hint}") from None
    except ValueError as e:
        raise FlexcalError(f"--port {url}: {e}; give a port such as /dev/ttyACM0 or COM3, or a pyserial URL") from None


class SerialReader:
    """Background line reader. Use as a context manager, or call ``start()`` and ``close()``.

    Parameters
    ----------
    url : str
        Port path or pyserial URL.
    baud : int
    max_line : int
        Longest line kept, in bytes; longer partial lines are dropped.
    reconnect : bool
        After a disconnect, keep trying to reopen the port (every ``retry_s``).
    """

    def __init__(self, url: str, *, baud: int = BAUD, max_line: int = 1024, reconnect: bool = False,
                 retry_s: float = 0.5, port=None):
        self.url, self.baud, self.max_line = url, baud, int(max_line)
        self.reconnect, self.retry_s = reconnect, retry_s
        self.queue: queue.Queue = queue.Queue()
        self.lines_read = 0
        self.bytes_dropped = 0
        self._port = port
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> "SerialReader":
        if self._port is None:
            self._port = open_port(self.url, self.baud)
        self._thread = threading.Thread(target=self._run, name=f"serial {self.url}", daemon=True)
        self._thread.start()
        return self

    def write(self, data: bytes) -> None:
        """Send bytes to the device (commands end in a newline)."""
        if self._port is not None:
            self._port.write(data)

    def close(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2)
        if self._port is not None:
            try:
                self._port.close()
            except Exception:  # noqa: BLE001 - closing a vanished port may fail in many ways
                pass

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.close()

    def get(self, timeout: float = 0.1):
        """The next Line or Event, or None after ``timeout`` seconds."""
        try:
            return self.queue.get(timeout=timeout)
        except queue.Empty:
            return None

    def _run(self):
        buf = bytearray()
        while not self._stop.is_set():
            try:
                waiting = self._port.in_waiting
                chunk = self._port.read(waiting if waiting else 1)   # 1 byte: block up to the timeout
            except (serial.SerialException, OSError) as e:
                self.queue.put(Event(time.monotonic(), "disconnected", str(e)))
                if not self.reconnect or not self._reopen():
                    return
                buf.clear()
                continue
            if not chunk:
                continue
            now = time.monotonic()
            buf += chunk
            while True:
                i = buf.find(b"\n")
                if i < 0:
                    break
                raw = bytes(buf[:i])
                del buf[: i + 1]
                if len(raw) > self.max_line:
                    self.bytes_dropped += len(raw)
                    self.queue.put(Event(now, "overlong", f"a {len(raw)}-byte line dropped"))
                    continue
                self.lines_read += 1
                self.queue.put(Line(now, raw.decode("utf-8", "replace").rstrip("\r")))
            if len(buf) > self.max_line:
                self.bytes_dropped += len(buf)
                self.queue.put(Event(now, "overlong", f"{len(buf)} bytes without a newline dropped"))
                buf.clear()

    def _reopen(self) -> bool:
        try:
            self._port.close()
        except Exception:  # noqa: BLE001
            pass
        while not self._stop.is_set():
            time.sleep(self.retry_s)
            try:
                self._port = serial.serial_for_url(self.url, baudrate=self.baud, timeout=0.05)
            except (serial.SerialException, OSError, ValueError):
                continue
            self.queue.put(Event(time.monotonic(), "reconnected", self.url))
            return True
        return False
