"""Mapping the device's clock (t_ms) onto the host's (monotonic seconds), online.

USB delivers a sample some time after the device stamped it; that latency is never
negative and has spikes. So the host time of a sample is at least offset + rate *
t_device, and the fit is the lower envelope: the rate (drift) from a least-squares
line, the offset from a low quantile of what is left. Each sample then gets the host
time it was taken at, with the USB jitter removed.
"""

from __future__ import annotations

from collections import deque

import numpy as np


class ClockFit:
    """Online fit t_host = offset + rate * t_device over a sliding history.

    Parameters
    ----------
    history : int
        Pairs kept (the newest), enough to span the drift's time scale.
    refit_every : int
        Refit after this many new pairs.
    quantile : float
        Quantile of the residuals taken as the zero-latency envelope.
    """

    def __init__(self, *, history: int = 20_000, refit_every: int = 50, quantile: float = 0.02):
        self.dev = deque(maxlen=history)
        self.host = deque(maxlen=history)
        self.refit_every, self.quantile = refit_every, quantile
        self.rate, self.offset = 1.0, None
        self._since = 0
        self.t0_dev = None

    def add(self, t_device_s: float, t_host_s: float) -> None:
        if self.t0_dev is None:
            self.t0_dev = t_device_s
        self.dev.append(t_device_s - self.t0_dev)
        self.host.append(t_host_s)
        self._since += 1
        if self.offset is None or self._since >= self.refit_every:
            self.refit()

    def refit(self) -> None:
        d, h = np.asarray(self.dev), np.asarray(self.host)
        if d.size >= 20 and np.ptp(d) > 0:
            # the rate from a line through the lower envelope of each stretch (robust to spikes)
            k = max(2, min(20, d.size // 20))
            parts = np.array_split(np.arange(d.size), k)
            low = [p[np.argmin(h[p] - d[p])] for p in parts if p.size]
            if len(low) >= 2 and np.ptp(d[low]) > 0:
                self.rate = float(np.polyfit(d[low], h[low], 1)[0])
        self.offset = float(np.quantile(h - self.rate * d, self.quantile))
        self._since = 0

    def host_time(self, t_device_s):
        """Host time (s) at which the device stamped ``t_device_s`` (array in, array out)."""
        if self.offset is None:
            return np.asarray(t_device_s, float) * np.nan
        return self.offset + self.rate * (np.asarray(t_device_s, float) - self.t0_dev)

    @property
    def drift_ppm(self) -> float:
        return (self.rate - 1.0) * 1e6

    def jitter_s(self) -> dict:
        """Latency left after the fit: median, 95th percentile and max (s), over the history."""
        d, h = np.asarray(self.dev), np.asarray(self.host)
        if self.offset is None or d.size == 0:
            return {"median_s": float("nan"), "p95_s": float("nan"), "max_s": float("nan")}
        r = h - (self.offset + self.rate * d)
        return {"median_s": float(np.median(r)), "p95_s": float(np.percentile(r, 95)), "max_s": float(r.max())}

    def summary(self) -> dict:
        return {"drift_ppm": self.drift_ppm, "offset_s": self.offset, "pairs": len(self.dev),
                "latency_after_fit": self.jitter_s()}
