"""Pairing photos with serial readings: the pairs table of DESIGN.md.

Each photo gets a time: from ``frames.csv`` when the trial has one, otherwise from the
photo's EXIF (aligned to the log's plateaus, since the camera's clock is not the log's),
otherwise photos are matched in order to the steady plateaus of the log. Around that
time the pair takes the median resistance of the steady samples, their spread and
count, and says whether the signal was steady.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from flexcal.capture.images import exif_time_s
from flexcal.capture.plateaus import find_plateaus, steady_mask
from flexcal.errors import FlexcalError

PAIR_COLUMNS = ["trial", "image", "t_s", "angle_actual_deg", "angle_actual_unc_deg", "resistance_ohm",
                "resistance_std_ohm", "n_samples", "angle_measured_deg", "steady"]
#: extra columns: how the photo got its time, and the vision status and reason
PAIR_EXTRA = ["time_source", "status", "reason"]

MIN_STEADY_SAMPLES = 5


def text_values(values, default: str = "") -> list:
    """The strings of a text column that may hold NaN (pandas reads empty cells as NaN):
    missing or empty -> ``default``."""
    return [v if isinstance(v, str) and v else default for v in values]


def read_frames(path) -> pd.DataFrame:
    """frames.csv: ``image, t_s`` (+ optional columns). One-line errors name the file."""
    path = Path(path)
    try:
        df = pd.read_csv(path, encoding="utf-8-sig")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as e:
        raise FlexcalError(f"{path}: cannot read it as a CSV table ({e}); it should have columns image,t_s") from None
    df.columns = [str(c).strip() for c in df.columns]
    missing = {"image", "t_s"} - set(df.columns)
    if missing:
        raise FlexcalError(f"{path}: missing column(s) {', '.join(sorted(missing))}; frames.csv needs image,t_s")
    t = pd.to_numeric(df["t_s"], errors="coerce")
    if t.isna().any():
        line = int(t.isna().to_numpy().argmax()) + 2
        raise FlexcalError(f"{path}, line {line}: t_s is not a number; fix or delete that row")
    df["t_s"] = t
    df["image"] = df["image"].astype(str).map(lambda s: Path(s).name)
    return df


def photo_times(images: list[Path], samples: pd.DataFrame, *, frames: pd.DataFrame | None = None,
                min_hold_s: float = 1.0):
    """Time of each photo on the log's clock, and how it was found.

    Returns ``(t_s array, source str, plateaus DataFrame or None, notes list)``. With
    ``source == "plateau order"`` the times are the plateaus' middles, and the i-th
    photo (sorted) belongs to the i-th plateau. With frames.csv no plateaus are needed
    (None).
    """
    notes: list[str] = []
    if frames is not None:
        by_name = dict(zip(frames["image"], frames["t_s"]))
        t = np.array([by_name.get(p.name, np.nan) for p in images], float)
        missing = [p.name for p, v in zip(images, t) if not np.isfinite(v)]
        if missing:
            notes.append(f"{len(missing)} photo(s) not in frames.csv (no time): {', '.join(missing[:3])}")
        return t, "frames.csv", None, notes
    plateaus = find_plateaus(samples["t_s"], samples["resistance_ohm"], min_hold_s=min_hold_s)
    exif = [exif_time_s(p) for p in images]
    timed = samples["t_s"].notna().all()
    if timed and images and all(e is not None for e in exif) and len(plateaus):
        t, note = _align_exif(np.array(exif, float), plateaus)
        notes.append(note)
        return t, "EXIF", plateaus, notes
    if len(plateaus) != len(images):
        raise FlexcalError(
            f"{len(images)} photo(s) but {len(plateaus)} steady plateau(s) in the log, and no frames.csv or EXIF "
            "times to match them; add frames.csv (image,t_s) or remove the extra "
            + ("photos" if len(images) > len(plateaus) else "plateaus (trim the log)"))
    mid = (plateaus["i_start"] + plateaus["i_end"] - 1) // 2
    t = samples["t_s"].to_numpy(float)[mid.to_numpy()] if timed else np.full(len(images), np.nan)
    return t, "plateau order", plateaus, notes


def _align_exif(exif: np.ndarray, plateaus: pd.DataFrame) -> tuple[np.ndarray, str]:
    """Shift EXIF times onto the log's clock: the offset putting most photos inside plateaus."""
    mids = ((plateaus["t_start_s"] + plateaus["t_end_s"]) / 2).to_numpy()
    starts, ends = plateaus["t_start_s"].to_numpy(), plateaus["t_end_s"].to_numpy()
    best = (-1, np.inf, 0.0)
    for off in (mids[:, None] - exif[None, :]).ravel():
        t = exif + off
        inside = (t[:, None] >= starts[None, :]) & (t[:, None] <= ends[None, :])
        hits = len(set(np.flatnonzero(inside.any(axis=0))))
        miss = np.abs(t[:, None] - mids[None, :]).min(axis=1).sum()
        if (hits, -miss) > (best[0], -best[1]):
            best = (hits, miss, off)
    hits, _, off = best
    return exif + off, f"EXIF times shifted by {off:+.1f} s onto the log's clock; {hits}/{len(exif)} inside plateaus"


def pair_trial(trial: str, images: list[Path], angles: pd.DataFrame, samples: pd.DataFrame, *,
               frames: pd.DataFrame | None = None, window_s: float = 2.0, min_hold_s: float = 1.0):
    """The pairs of one trial.

    Parameters
    ----------
    trial : str
        The trial's name (its folder name).
    images : list of Path
        The trial's photos, sorted.
    angles : DataFrame
        Angles table rows for these photos, in the same order (``angle_deg``,
        ``angle_unc_deg``, ``status``, ``reason``).
    samples : DataFrame
        The trial's serial samples (``read_log``).
    frames : DataFrame, optional
        ``read_frames`` of the trial's frames.csv.
    window_s : float
        Width of the window around each photo's time (seconds).

    Returns
    -------
    (pairs DataFrame with PAIR_COLUMNS + PAIR_EXTRA, list of notes)
    """
    if len(angles) != len(images):
        raise ValueError("angles must have one row per image")
    t_photo, source, plateaus, notes = photo_times(images, samples, frames=frames, min_hold_s=min_hold_s)
    t = samples["t_s"].to_numpy(float)
    r = samples["resistance_ohm"].to_numpy(float)
    a = samples["angle_deg"].to_numpy(float)
    steady = steady_mask(t if np.isfinite(t).all() else np.full_like(r, np.nan), r)
    if source != "plateau order" and np.isfinite(t).all() and np.any(np.diff(t) < 0):
        i = int(np.flatnonzero(np.diff(t) < 0)[0]) + 1
        raise FlexcalError(f"trial {trial}: the log's time goes backwards at line {int(samples['line'].iloc[i])} "
                           f"({t[i]:g} s after {t[i - 1]:g} s; did the device reset?); split the log there or "
                           "remove the earlier part")
    rows = []
    for k, (img, tp) in enumerate(zip(images, t_photo)):
        row = dict(trial=trial, image=str(img), t_s=tp, time_source=source)
        if source == "plateau order":
            p = plateaus.iloc[k]
            sel = np.zeros(len(r), bool)
            sel[int(p.i_start):int(p.i_end)] = True
        elif np.isfinite(tp):
            sel = np.abs(t - tp) <= window_s / 2
        else:
            sel = np.zeros(len(r), bool)
        use = sel & steady & np.isfinite(r)
        is_steady = use.sum() >= max(MIN_STEADY_SAMPLES, 0.5 * sel.sum())
        if not is_steady:
            use = sel & np.isfinite(r)
        row.update(resistance_ohm=float(np.median(r[use])) if use.any() else np.nan,
                   resistance_std_ohm=float(np.std(r[use], ddof=1)) if use.sum() > 1 else np.nan,
                   n_samples=int(use.sum()),
                   angle_measured_deg=float(np.median(a[use])) if use.any() else np.nan,
                   steady=bool(is_steady and use.any()))
        rows.append(row)
    pairs = pd.DataFrame(rows)
    for col in ("angle_deg", "angle_unc_deg", "status", "reason"):
        if col not in angles:
            angles = angles.assign(**{col: np.nan if col.startswith("angle") else ("ok" if col == "status" else "")})
    pairs["angle_actual_deg"] = angles["angle_deg"].to_numpy(float)
    pairs["angle_actual_unc_deg"] = angles["angle_unc_deg"].to_numpy(float)
    pairs["status"] = text_values(angles["status"], "ok")
    pairs["reason"] = text_values(angles["reason"])
    no_samples = pairs["n_samples"] == 0
    if no_samples.any():
        lo, hi = np.nanmin(t) if np.isfinite(t).any() else np.nan, np.nanmax(t) if np.isfinite(t).any() else np.nan
        notes.append(f"trial {trial}: {int(no_samples.sum())} photo(s) have no serial samples within "
                     f"±{window_s / 2:g} s (the log covers {lo:.1f}...{hi:.1f} s); are frames.csv and the log on one clock?")
    return pairs[PAIR_COLUMNS + PAIR_EXTRA], notes
