"""Mapping the device's clock (t_ms) onto the host's (monotonic seconds), online.

USB delivers a sample some time after the device stamped it; that latency is never
negative and has spikes. So the host time of a sample is at least offset + rate *
t_device: the fit follows the lower envelope. Each bin of device time (1 s) keeps its
least-delayed sample; the rate (the crystal's drift) is a line through those minima
over the whole session, the offset a low quantile of what is left. Memory stays
bounded (one pair per bin), and a long session's drift is measured over all of it.
"""

from __future__ import annotations

from collections import deque

import numpy as np


class ClockFit:
    """Online fit t_host = offset + rate * (t_device - first t_device).

    Parameters
    ----------
    bin_s : float
        Width of the device-time bins whose least-delayed pair is kept.
    max_bins : int
        Bins kept (the newest); 100 000 one-second bins cover 27 hours.
    refit_every : int
        Refit after this many new pairs.
    quantile : float
        Quantile of the bin minima's residuals taken as the zero-latency envelope.
    recent : int
        Raw pairs kept for the latency report.
    """

    def __init__(self, *, bin_s: float = 1.0, max_bins: int = 100_000, refit_every: int = 50,
                 quantile: float = 0.1, recent: int = 20_000):
        self.bin_s, self.refit_every, self.quantile = bin_s, refit_every, quantile
        self.bins: dict[int, tuple[float, float]] = {}
        self._order: deque = deque(maxlen=max_bins)
        self.recent_dev: deque = deque(maxlen=recent)
        self.recent_host: deque = deque(maxlen=recent)
        self.rate, self.offset = 1.0, None
        self.pairs = 0
        self._since = 0
        self.t0_dev = None

    def add(self, t_device_s: float, t_host_s: float) -> None:
        if self.t0_dev is None:
            self.t0_dev = t_device_s
        d = t_device_s - self.t0_dev
        k = int(d // self.bin_s)
        best = self.bins.get(k)
        if best is None:
            if len(self._order) == self._order.maxlen:
                self.bins.pop(self._order[0], None)
            self._order.append(k)
            self.bins[k] = (d, t_host_s)
        elif t_host_s - d < best[1] - best[0]:
            self.bins[k] = (d, t_host_s)
        self.recent_dev.append(d)
        self.recent_host.append(t_host_s)
        self.pairs += 1
        self._since += 1
        if self.offset is None or self._since >= self.refit_every:
            self.refit()

    def refit(self) -> None:
        mins = np.array(list(self.bins.values()))
        d, h = mins[:, 0], mins[:, 1]
        if d.size >= 3 and np.ptp(d) > 0:
            # a robust line through the bins' minima: refit without the worst quarter once
            rate, icpt = np.polyfit(d, h, 1)
            res = h - (icpt + rate * d)
            keep = res <= np.quantile(res, 0.75)
            if keep.sum() >= 3 and np.ptp(d[keep]) > 0:
                rate = np.polyfit(d[keep], h[keep], 1)[0]
            self.rate = float(rate)
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
        """Latency left after the fit over the recent pairs: median, 95th percentile and max (s)."""
        d, h = np.asarray(self.recent_dev), np.asarray(self.recent_host)
        if self.offset is None or d.size == 0:
            return {"median_s": float("nan"), "p95_s": float("nan"), "max_s": float("nan")}
        r = h - (self.offset + self.rate * d)
        return {"median_s": float(np.median(r)), "p95_s": float(np.percentile(r, 95)), "max_s": float(r.max())}

    def summary(self) -> dict:
        return {"drift_ppm": self.drift_ppm, "offset_s": self.offset, "pairs": self.pairs, "bins": len(self.bins),
                "latency_after_fit": self.jitter_s()}
