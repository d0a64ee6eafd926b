"""``calibrate``: from trials on disk to calibration.json, figures, report.html and the firmware header.

Also ``apply_calibration``, the library side of ``flexcal apply``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from flexcal.calibration import reference
from flexcal.calibration.experiment import Trial, build_pairs
from flexcal.calibration.export import calibration_dict, header_text, load, sha256, write_json
from flexcal.calibration.fit import fit_calibration, fit_pressure
from flexcal.calibration.mapping import OutOfRange
from flexcal.calibration.report import make_figures, write_report
from flexcal.capture.logs import read_log
from flexcal.errors import FlexcalError


def read_pressure(path, contact_area_in2: float = reference.CONTACT_AREA_IN2):
    path = Path(path)
    if not path.is_file():
        raise FlexcalError(f"--pressure {path}: no such file; give the pressure table (mass_g,trial,angle_deg,"
                           "resistance_ohm)")
    try:
        table = pd.read_csv(path, encoding="utf-8-sig", sep=None, engine="python")
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        raise FlexcalError(f"--pressure {path}: cannot read it as a table ({e})") from None
    table.columns = [str(c).strip() for c in table.columns]
    return fit_pressure(table, contact_area_in2, source=str(path))


def calibrate(trials: list[Trial], out_dir, *, angles: pd.DataFrame | None = None, angles_path=None,
              pressure_path=None, contact_area_in2: float = reference.CONTACT_AREA_IN2, divider=None,
              window_s: float = 2.0, jobs=None, overlays: bool = True, progress: bool = True) -> dict:
    """Run the whole calibration and write its outputs into ``out_dir``.

    Writes ``angles.csv`` (when photos were measured), ``overlays/`` (with ``overlays``),
    ``pairs.csv``, ``steps.csv`` (per-step mean and sd across trials), ``calibration.json``, ``figures/*.png``, ``report.html`` and
    ``flexcal_calibration.h``. Returns the calibration.json data plus ``result`` (the
    ``CalibrationResult``) and ``paths``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    pressure = read_pressure(pressure_path, contact_area_in2) if pressure_path else None
    overlay_dir = out / "overlays" if (overlays and angles is None) else None
    pairs, angles_table, logs, notes = build_pairs(trials, angles=angles, divider=divider, window_s=window_s,
                                                   jobs=jobs, overlay_dir=overlay_dir, progress=progress)
    paths = {}
    if angles is None:
        paths["angles"] = out / "angles.csv"
        angles_table.to_csv(paths["angles"], index=False, float_format="%.4f")
    result = fit_calibration(pairs, pressure=pressure)
    result.notes[:0] = notes
    paths["pairs"] = out / "pairs.csv"
    result.pairs.to_csv(paths["pairs"], index=False, float_format="%.6g")

    paths["steps"] = out / "steps.csv"
    result.steps.to_csv(paths["steps"], index=False, float_format="%.6g")

    def log_reading(info):
        return None if info is None else {
            "dialect": info.dialect, "resistance_unit": info.resistance_unit, "time_source": info.time_source,
            "angle_source": info.angle_source, "samples": info.n_samples, "unreadable_lines": info.bad_lines}

    inputs = {"trials": [{
        "name": t.name, "log": str(t.log), "log_sha256": sha256(t.log),
        "frames": str(t.frames) if t.frames else None, "frames_sha256": sha256(t.frames) if t.frames else None,
        "log_reading": log_reading(logs.get(t.name)),
        "images": [{"file": str(i), "sha256": sha256(i)} for i in t.images]} for t in trials]}
    inputs["angles"] = ({"source": "vision (flexcal.vision)"} if angles is None else
                        {"source": str(angles_path), "sha256": sha256(angles_path) if angles_path else None})
    if pressure_path:
        inputs["pressure"] = {"file": str(pressure_path), "sha256": sha256(pressure_path)}
    parameters = {"window_s": window_s, "contact_area_in2": contact_area_in2,
                  "divider": None if divider is None else divider.__dict__}
    data = calibration_dict(result, inputs=inputs, parameters=parameters)
    paths["calibration"] = out / "calibration.json"
    write_json(data, paths["calibration"])
    figs = make_figures(result, out / "figures")
    paths["report"] = out / "report.html"
    overlay_files = {}
    if overlay_dir is not None:
        from flexcal.measure import overlay_names

        images = [img for t in trials for img in t.images]
        overlay_files = {str(i): overlay_dir / n for i, n in zip(images, overlay_names(images))}
    write_report(result, data, figs, paths["report"], overlays_dir=overlay_dir, overlays=overlay_files)
    paths["header"] = out / "flexcal_calibration.h"
    paths["header"].write_text(header_text(data))
    return {**data, "result": result, "paths": paths}


def apply_calibration(calibration_path, log_path, out_path, *, mapping: str | None = None,
                      extrapolate: bool = False, divider=None) -> pd.DataFrame:
    """Add ``angle_corrected_deg`` (recommended or named mapping) and ``angle_<name>_deg`` for every
    mapping to a log; write it to ``out_path``. Readings outside the calibrated range are refused
    (FlexcalError naming the first) unless ``extrapolate``, which marks them in ``extrapolated``."""
    cal = load(calibration_path)
    df = read_log(log_path, divider=divider)
    r = df["resistance_ohm"].to_numpy(float)
    chosen = cal.mapping(mapping)
    lo, hi = chosen.resistance_range_ohm
    try:
        df["angle_corrected_deg"] = cal.angle_deg(r, mapping=mapping, extrapolate=extrapolate)
    except OutOfRange as e:
        i = int(np.flatnonzero(np.isfinite(r) & ((r < lo) | (r > hi)))[0])
        raise FlexcalError(f"{log_path}, line {int(df['line'].iloc[i])}: {e}; calibrate over a wider range of "
                           "angles, or add --extrapolate to map them anyway") from None
    for name, m in cal.mappings.items():
        df[f"angle_{name}_deg"] = m.angle_deg(r, extrapolate=True)
    df["extrapolated"] = np.isfinite(r) & ((r < lo) | (r > hi))
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(out, index=False, float_format="%.6g")
    return df
