"""An experiment on disk: finding its trials, measuring their photos, building the pairs table.

A trial is a folder of photos plus a serial log (DESIGN.md's trial folder, or an old
experiment's photos and log given side by side). ``build_pairs`` reads every log,
measures every photo (or takes ``--angles``), and pairs them trial by trial.
"""

from __future__ import annotations

import glob
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from flexcal.calibration.pairing import PAIR_COLUMNS, PAIR_EXTRA, pair_trial, read_frames, text_values
from flexcal.capture.images import find_images, photo_folder
from flexcal.capture.logs import read_log
from flexcal.errors import FlexcalError

_NOT_LOGS = {"frames.csv", "truth.csv", "angles.csv", "pairs.csv", "pressure.csv", "meta.json"}


@dataclass(frozen=True)
class Trial:
    """One trial: its name, its photos (sorted), its serial log and, if there is one, frames.csv."""

    name: str
    images: tuple
    log: Path
    frames: Path | None = None


def _find_log(folder: Path) -> Path | None:
    if (folder / "serial.csv").is_file():
        return folder / "serial.csv"
    cands = sorted(f for f in folder.iterdir() if f.is_file() and f.suffix.lower() in (".csv", ".txt", ".log")
                   and f.name not in _NOT_LOGS)
    return cands[0] if len(cands) == 1 else None


def _trial_at(folder: Path) -> Trial | None:
    """A folder is a trial when it holds photos (in images/ or itself) and one serial log."""
    img_dir = photo_folder(folder)
    images = find_images([img_dir])
    log = _find_log(folder)
    if not images or log is None:
        return None
    frames = next((f for f in (img_dir / "frames.csv", folder / "frames.csv") if f.is_file()), None)
    return Trial(folder.name, tuple(images), log, frames)


def find_trials(dirs) -> list[Trial]:
    """Trials under ``--trials DIR...``: each DIR is a trial folder or holds trial folders."""
    trials: list[Trial] = []
    for d in _expand(dirs, "--trials"):
        if not d.is_dir():
            raise FlexcalError(f"--trials {d}: not a folder; give the experiment folder holding trial_* folders")
        t = _trial_at(d)
        found = [t] if t else [x for x in (_trial_at(s) for s in sorted(d.iterdir()) if s.is_dir()) if x]
        if not found:
            raise FlexcalError(f"--trials {d}: no trial folders in it (a trial folder holds images/ and serial.csv)")
        trials += found
    names = [t.name for t in trials]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        trials = [Trial(f"{t.log.parent.parent.name}/{t.name}" if t.name in dup else t.name, t.images, t.log, t.frames)
                  for t in trials]
    return trials


def _expand(items, arg) -> list[Path]:
    out = []
    for item in items:
        s = str(item)
        matches = sorted(glob.glob(s)) if glob.has_magic(s) else [s]
        if not matches or not all(Path(m).exists() for m in matches):
            raise FlexcalError(f"{arg} {s}: no such file or folder; check the path (quote globs)")
        out += [Path(m) for m in matches]
    return out


def trials_from_args(images, logs) -> list[Trial]:
    """Trials from ``--images DIR... --log FILE...``, matched in the order given."""
    img_dirs = _expand(images, "--images")
    log_files = _expand(logs, "--log")
    for d in img_dirs:
        if not d.is_dir():
            raise FlexcalError(f"--images {d}: not a folder; give the folder of a trial's photos")
    for f in log_files:
        if not f.is_file():
            raise FlexcalError(f"--log {f}: not a file; give the serial log (e.g. serial.csv)")
    if len(img_dirs) != len(log_files):
        raise FlexcalError(f"{len(img_dirs)} --images folder(s) but {len(log_files)} --log file(s); give one log per "
                           "folder of photos, in the same order (or use --trials DIR)")
    trials = []
    for d, log in zip(img_dirs, log_files):
        images = find_images([d])
        if not images:
            raise FlexcalError(f"--images {d}: no photos in it (.jpg, .png, .tif ...)")
        frames = next((f for f in (d / "frames.csv", d.parent / "frames.csv") if f.is_file()), None)
        name = d.parent.name if d.name == "images" else d.name
        trials.append(Trial(name, tuple(images), log, frames))
    return trials


def read_angles(path) -> pd.DataFrame:
    """An angles table for ``--angles``: the output of ``flexcal measure`` or any image,angle_deg CSV."""
    path = Path(path)
    if not path.is_file():
        raise FlexcalError(f"--angles {path}: no such file; give the angles table written by flexcal measure")
    try:
        df = pd.read_csv(path, encoding="utf-8-sig")
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        raise FlexcalError(f"--angles {path}: cannot read it as a CSV table ({e})") from None
    if not {"image", "angle_deg"} <= set(df.columns):
        raise FlexcalError(f"--angles {path}: needs columns image and angle_deg (found {', '.join(df.columns)})")
    df["angle_deg"] = pd.to_numeric(df["angle_deg"], errors="coerce")
    for col, default in (("angle_unc_deg", np.nan), ("status", "ok"), ("reason", "")):
        if col not in df:
            df[col] = default
    df.loc[df["angle_deg"].isna() & (df["status"] == "ok"), "status"] = "failed"
    return df


def _angles_for(trial: Trial, table: pd.DataFrame, source: str) -> pd.DataFrame:
    """Rows of an angles table for a trial's photos, matched by path, then trial/name, then name."""
    keys = table["image"].astype(str)
    full = {str(Path(k).resolve()): i for i, k in enumerate(keys)}
    by_name: dict[str, list[int]] = {}
    for i, k in enumerate(keys):
        by_name.setdefault(Path(k).name, []).append(i)
    rows = []
    for img in trial.images:
        i = full.get(str(img.resolve()))
        if i is None:
            cands = by_name.get(img.name, [])
            inside = [j for j in cands if trial.name in Path(keys.iloc[j]).parts]
            i = inside[0] if len(inside) == 1 else (cands[0] if len(cands) == 1 else None)
        if i is None:
            rows.append(dict(angle_deg=np.nan, angle_unc_deg=np.nan, status="failed",
                             reason=f"not in {source}"))
        else:
            rows.append(table.iloc[i][["angle_deg", "angle_unc_deg", "status", "reason"]].to_dict())
    return pd.DataFrame(rows)


def build_pairs(trials: list[Trial], *, angles: pd.DataFrame | None = None, angles_source: str = "--angles",
                divider=None, window_s: float = 2.0, jobs=None, overlay_dir=None, progress: bool = True):
    """Read, measure and pair every trial.

    Returns ``(pairs, angles_table, logs, notes)``: the pairs table (DESIGN.md columns,
    plus ``step``, ``time_source``, ``status``, ``reason``, ``pairing_error``), the
    angles table of every photo, ``{trial: LogInfo}`` and a list of notes for the
    report. A trial whose log cannot be read or paired keeps its photos as rows with
    ``pairing_error`` set, and the others carry on.
    """
    if not trials:
        raise FlexcalError("no trials given; use --images DIR --log FILE, or --trials DIR")
    notes: list[str] = []
    logs, samples, broken = {}, {}, {}
    for t in trials:
        try:
            df = read_log(t.log, divider=divider)
        except FlexcalError as e:   # one bad log must not sink the other trials
            broken[t.name] = str(e)
            continue
        samples[t.name], logs[t.name] = df, df.attrs["log"]
        if logs[t.name].bad_lines:
            notes.append(logs[t.name].summary())
        notes += [f"{t.log}: {n}" for n in logs[t.name].notes if not n.startswith("line ")]
    if angles is None:
        from flexcal.measure import measure_files

        all_images = [img for t in trials for img in t.images]
        angles = measure_files(all_images, jobs=jobs, overlay_dir=overlay_dir, progress=progress)
        angles_source = "vision"
    parts = []
    for t in trials:
        a = _angles_for(t, angles, angles_source)
        try:
            if t.name in broken:
                raise FlexcalError(broken[t.name])
            frames = read_frames(t.frames) if t.frames else None
            p, n = pair_trial(t.name, list(t.images), a, samples[t.name], frames=frames, window_s=window_s)
            p["pairing_error"] = ""
        except FlexcalError as e:
            msg = str(e) if str(e).startswith(str(t.log)) else f"{t.log}: {e}"
            notes.append(f"trial {t.name} left out: {msg}")
            p, n, frames = _unpaired(t, a, msg), [], None
        if frames is not None and "step" in frames:
            steps = dict(zip(frames["image"], frames["step"]))
            p["step"] = [steps.get(Path(i).name, np.nan) for i in p["image"]]
        else:
            p["step"] = np.arange(1, len(p) + 1)
        parts.append(p)
        notes += n
    pairs = pd.concat(parts, ignore_index=True)
    return pairs[PAIR_COLUMNS + ["step"] + PAIR_EXTRA + ["pairing_error"]], angles, logs, notes


def _unpaired(t: Trial, angles: pd.DataFrame, why: str) -> pd.DataFrame:
    """Rows for a trial that could not be paired: every photo kept, with the reason."""
    return pd.DataFrame({
        "trial": t.name, "image": [str(i) for i in t.images], "t_s": np.nan,
        "angle_actual_deg": angles["angle_deg"].to_numpy(float),
        "angle_actual_unc_deg": angles["angle_unc_deg"].to_numpy(float), "resistance_ohm": np.nan,
        "resistance_std_ohm": np.nan, "n_samples": 0, "angle_measured_deg": np.nan, "steady": False,
        "time_source": "", "status": text_values(angles["status"], "ok"), "reason": text_values(angles["reason"]),
        "pairing_error": why})
