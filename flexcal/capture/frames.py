"""Frame sources for capture: a camera by index, a video file, or an image sequence.

All through ``cv2.VideoCapture``, read continuously on a background thread so that
"take a photo" returns the newest frame, stamped with the host's monotonic clock when
it was read. A video file or image sequence plays at its frame rate from ``start()``,
as a camera would deliver it.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path

import cv2
import numpy as np

from flexcal.capture.images import IMAGE_SUFFIXES, find_images
from flexcal.errors import FlexcalError


class FrameSource:
    """The newest frame of a camera, video file or image sequence.

    Parameters
    ----------
    source : int or str
        Camera index (``0``), a video file, or an image sequence: a printf pattern
        (``frames/img_%04d.png``) or a folder of images (played in name order).
    fps : float, optional
        Frame rate for a file or sequence (default: the file's own, else 10).
    loop : bool
        Start a file again at its end instead of holding its last frame.
    """

    def __init__(self, source, *, fps: float | None = None, loop: bool = False):
        self.source, self.loop = source, loop
        self.is_camera = isinstance(source, int) or (isinstance(source, str) and source.isdigit())
        self._files: list[Path] | None = None
        if self.is_camera:
            self._cap = cv2.VideoCapture(int(source))
        else:
            p = Path(str(source))
            if p.is_dir():
                self._files = [f for f in find_images([p]) if f.suffix.lower() in IMAGE_SUFFIXES]
                if not self._files:
                    raise FlexcalError(f"--camera {source}: no images in that folder")
                self._cap = None
            elif not p.exists() and "%" not in str(source):
                raise FlexcalError(f"--camera {source}: no such file; give a camera index (0), a video file or "
                                   "a folder of images")
            else:
                self._cap = cv2.VideoCapture(str(source))
        if self._cap is not None and not self._cap.isOpened():
            what = "camera" if self.is_camera else "video"
            raise FlexcalError(f"--camera {source}: cannot open the {what}"
                               + ("; is it connected and not in use by another program?" if self.is_camera
                                  else "; is it a video OpenCV can read (mp4, avi)?"))
        own = self._cap.get(cv2.CAP_PROP_FPS) if self._cap is not None else 0
        self.fps = float(fps or (own if own and own > 0 else 10.0))
        self._lock = threading.Lock()
        self._frame: np.ndarray | None = None
        self._t = float("nan")
        self._index = -1
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.error = ""

    def start(self) -> "FrameSource":
        self._thread = threading.Thread(target=self._run, name="frames", daemon=True)
        self._thread.start()
        return self

    def _read_next(self, k: int):
        if self._files is not None:
            if k >= len(self._files):
                if not self.loop:
                    return None
                k %= len(self._files)
            return cv2.imread(str(self._files[k]), cv2.IMREAD_COLOR)
        ok, frame = self._cap.read()
        if not ok and self.loop and not self.is_camera:
            self._cap.set(cv2.CAP_PROP_POS_FRAMES, 0)
            ok, frame = self._cap.read()
        return frame if ok else None

    def _run(self):
        t0 = time.monotonic()
        k = 0
        while not self._stop.is_set():
            if not self.is_camera:   # a file plays at its frame rate
                wait = t0 + k / self.fps - time.monotonic()
                if wait > 0:
                    time.sleep(wait)
            frame = self._read_next(k)
            now = time.monotonic()
            if frame is None:
                if self.is_camera:
                    self.error = "the camera stopped delivering frames"
                return   # a file that ended holds its last frame
            with self._lock:
                self._frame, self._t, self._index = frame, now, k
            k += 1

    def latest(self, *, after: float | None = None, timeout: float = 2.0):
        """The newest frame as ``(frame, t_host_s, index)``; with ``after``, wait for one read after it."""
        end = time.monotonic() + timeout
        while True:
            with self._lock:
                if self._frame is not None and (after is None or self._t >= after):
                    return self._frame.copy(), self._t, self._index
            if time.monotonic() > end:
                raise FlexcalError(f"--camera {self.source}: no frame within {timeout:g} s"
                                   + (f" ({self.error})" if self.error else ""))
            time.sleep(0.005)

    def close(self):
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2)
        if self._cap is not None:
            self._cap.release()

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.close()
