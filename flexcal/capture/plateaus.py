"""Steady plateaus in a resistance stream: where the finger was held still.

Shared by capture (to say "steady, take the photo") and calibration (to pair photos
with readings). The test is relative to the stream's own noise, so it needs no
threshold in ohm: the noise is estimated from sample-to-sample differences (robust to
the steps), and a sample is steady when the spread of a short window around it stays
within a few noise widths.
"""

from __future__ import annotations

from collections import deque

import numpy as np
import pandas as pd

PLATEAU_COLUMNS = ["plateau", "i_start", "i_end", "t_start_s", "t_end_s", "resistance_ohm", "resistance_std_ohm",
                   "n_samples"]


def noise_ohm(resistance_ohm) -> float:
    """Sample-to-sample noise (1 sigma, ohm), robust to steps: MAD of differences / sqrt 2."""
    r = np.asarray(resistance_ohm, float)
    d = np.diff(r[np.isfinite(r)])
    if d.size < 2:
        return float("nan")
    mad = 1.4826 * np.median(np.abs(d - np.median(d)))
    return float(mad / np.sqrt(2))


def _window_samples(t_s, window_s: float, default: int) -> int:
    t = np.asarray(t_s, float)
    if t.size > 2 and np.isfinite(t).all():
        dt = np.median(np.diff(t))
        if dt > 0:
            return max(3, int(round(window_s / dt)) | 1)
    return default


def steady_mask(t_s, resistance_ohm, *, window_s: float = 0.5, tolerance: float = 3.0,
                noise: float | None = None) -> np.ndarray:
    """True where the signal is steady.

    A sample is steady when the standard deviation of the centred window of
    ``window_s`` seconds around it (9 samples when there is no time) is at most
    ``tolerance`` times the noise (estimated with ``noise_ohm`` unless given), with a
    floor of 0.05 % of the level so a noiseless stream is not all unsteady.
    """
    r = pd.Series(np.asarray(resistance_ohm, float))
    w = _window_samples(t_s, window_s, default=9)
    sd = r.rolling(w, center=True, min_periods=max(2, w // 2)).std().to_numpy()
    sigma = noise_ohm(r) if noise is None else noise
    level = np.nanmedian(np.abs(r)) if r.notna().any() else 0.0
    return np.nan_to_num(sd, nan=np.inf) <= steady_limit(sigma, level, tolerance)


def steady_limit(noise: float, level: float, tolerance: float = 3.0) -> float:
    """The largest window standard deviation (ohm) that still counts as steady: ``tolerance``
    noise widths, with a floor of 0.05 % of the level (a noiseless stream)."""
    return max(tolerance * (noise if np.isfinite(noise) else 0.0), 5e-4 * abs(level))


class SteadyTracker:
    """Online steadiness of a live stream, by the same rule as ``steady_mask``.

    ``update(t_s, r)`` with each sample; ``steady_for_s`` says how long the signal has
    been steady (0 when it is not). The noise is estimated from the recent history: at
    every check until it rests on ``MIN_NOISE_SAMPLES`` samples (two or three first
    readings can be nearly equal and give a noise far too small, which would hold a
    steady signal unsteady), then every ``NOISE_EVERY`` samples.
    """

    MIN_NOISE_SAMPLES = 12
    NOISE_EVERY = 25

    def __init__(self, *, window_s: float = 0.5, tolerance: float = 3.0, history_s: float = 10.0,
                 check_every_s: float = 0.02):
        self.window_s, self.tolerance, self.history_s = window_s, tolerance, history_s
        self.check_every_s = check_every_s
        self._last_check: float | None = None
        self._last_t = float("nan")
        self._t: deque = deque()
        self._r: deque = deque()
        self._since: float | None = None
        self.noise = float("nan")
        self._n = 0
        self._noise_n = 0        # samples seen when the noise was last estimated

    def update(self, t_s: float, r: float) -> bool:
        if not np.isfinite(r):
            self._since = None
            return False
        self._t.append(t_s)
        self._r.append(r)
        while self._t and self._t[0] < t_s - self.history_s:
            self._t.popleft()
            self._r.popleft()
        self._n += 1
        self._last_t = t_s
        if self._last_check is not None and t_s - self._last_check < self.check_every_s:
            return self._since is not None      # at high rates, judge every check_every_s only
        self._last_check = t_s
        if self._noise_n < self.MIN_NOISE_SAMPLES or self._n - self._noise_n >= self.NOISE_EVERY:
            self.noise = noise_ohm(self._r)
            self._noise_n = self._n
        t = np.asarray(self._t)
        win = np.asarray(self._r)[t >= t_s - self.window_s]
        steady = win.size >= 3 and t_s - t[0] >= self.window_s and \
            float(np.std(win, ddof=1)) <= steady_limit(self.noise, float(np.median(win)), self.tolerance)
        if steady and self._since is None:
            self._since = t_s
        elif not steady:
            self._since = None
        return steady

    @property
    def steady_for_s(self) -> float:
        return 0.0 if self._since is None else self._last_t - self._since

    def level(self, window_s: float | None = None) -> float:
        """Median of the last ``window_s`` seconds (default: the steadiness window)."""
        t = np.asarray(self._t)
        if not t.size:
            return float("nan")
        w = np.asarray(self._r)[t >= t[-1] - (window_s or self.window_s)]
        return float(np.median(w))


def find_plateaus(t_s, resistance_ohm, *, min_hold_s: float = 1.0, window_s: float = 0.5,
                  tolerance: float = 3.0) -> pd.DataFrame:
    """The steady stretches of a stream, in time order.

    Parameters
    ----------
    t_s : (N,) array
        Sample times in seconds, or NaN throughout when the log has no time (then the
        durations are counted in samples at a nominal 50 Hz).
    resistance_ohm : (N,) array
    min_hold_s : float
        Shortest stretch that counts as a plateau.

    Returns
    -------
    DataFrame with ``plateau`` (1, 2, ...), ``i_start, i_end`` (row positions, end
    exclusive), ``t_start_s, t_end_s``, the median ``resistance_ohm``, its standard
    deviation and ``n_samples``. Adjacent stretches at one level, split by a spike,
    are merged.
    """
    r = np.asarray(resistance_ohm, float)
    t = np.asarray(t_s, float)
    timed = t.size == r.size and t.size > 2 and np.isfinite(t).all()
    if not timed:
        t = np.arange(r.size) / 50.0
    steady = steady_mask(t, r, window_s=window_s, tolerance=tolerance) & np.isfinite(r)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], steady.astype(int), [0]])))
    runs = list(zip(edges[::2], edges[1::2]))
    sigma = noise_ohm(r)
    merged: list[list[int]] = []
    for a, b in runs:
        if merged:
            pa, pb = merged[-1]
            same = abs(np.median(r[pa:pb]) - np.median(r[a:b])) <= 4 * max(sigma, 1e-9)
            if same and t[a] - t[pb - 1] < min_hold_s:
                merged[-1][1] = b
                continue
        merged.append([a, b])
    rows = []
    for a, b in merged:
        if t[b - 1] - t[a] < min_hold_s:
            continue
        seg = r[a:b][steady[a:b]]
        rows.append(dict(plateau=len(rows) + 1, i_start=int(a), i_end=int(b),
                         t_start_s=float(t[a]) if timed else np.nan, t_end_s=float(t[b - 1]) if timed else np.nan,
                         resistance_ohm=float(np.median(seg)), resistance_std_ohm=float(np.std(seg, ddof=1)),
                         n_samples=int(seg.size)))
    return pd.DataFrame(rows, columns=PLATEAU_COLUMNS)
