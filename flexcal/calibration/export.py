"""calibration.json (write and ``load``) and the firmware header flexcal_calibration.h.

The JSON schema is documented in docs/calibration-json.md; ``SCHEMA_VERSION`` changes
whenever a key changes meaning or disappears.
"""

from __future__ import annotations

import hashlib
import json
import math
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from flexcal import __version__
from flexcal.calibration import reference
from flexcal.calibration.mapping import mapping_from_dict
from flexcal.errors import FlexcalError

SCHEMA = "flexcal.calibration"
SCHEMA_VERSION = 1


def sha256(path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _clean(x):
    """JSON-safe: numpy scalars to Python, NaN/inf to None."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, np.ndarray):
        return _clean(x.tolist())
    if isinstance(x, (np.floating, float)):
        return None if not math.isfinite(float(x)) else float(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (np.bool_,)):
        return bool(x)
    if isinstance(x, Path):
        return str(x)
    return x


def calibration_dict(result, *, inputs: dict, parameters: dict) -> dict:
    """Everything a calibration holds, JSON-able (see docs/calibration-json.md)."""
    r = result

    used = r.used

    def span(values):
        v = np.asarray(values, float)
        return [float(np.nanmin(v)), float(np.nanmax(v))]

    def fit(f, x, y, ref=None, data=None):
        d = {"x": x, "y": y, **f.to_dict()}
        data = used if data is None else data
        if x in data and y in data:   # where the fit holds: the range of the data it was fitted to
            d["x_range"], d["y_range"] = span(data[x]), span(data[y])
        if ref is not None:
            d["reference"] = {"slope": ref[0], "intercept": ref[1]}
        return d

    models = {
        "eq16_resistance_vs_firmware_angle": fit(r.eq16, "angle_measured_deg", "resistance_ohm", reference.EQ16),
        "eq17_resistance_vs_photo_angle": fit(r.eq17, "angle_actual_deg", "resistance_ohm", reference.EQ17),
        "eq17_resistance_vs_photo_angle_ols": fit(r.eq17_ols, "angle_actual_deg", "resistance_ohm", reference.EQ17),
        "eq18_error": {**r.eq18, "reference": {"slope": reference.EQ18[0], "intercept": reference.EQ18[1]}},
        "eq18_error_direct": fit(r.eq18_direct, "angle_actual_deg", "resistance_ohm - eq16(angle_actual_deg)",
                                 reference.EQ18),
        "eq20_reference_form": {k: v for k, v in r.reference_model.items() if not isinstance(v, list)},
        "physical": r.physical_fit,
    }
    if r.pressure is not None:
        p = r.pressure
        models["pressure"] = {
            "contact_area_in2": p.contact_area_in2,
            "angle_vs_pressure": fit(p.angle_fit, "pressure_psi", "angle_deg", reference.ANGLE_VS_PRESSURE,
                                     p.table),
            "resistance_vs_pressure": fit(p.resistance_fit, "pressure_psi", "resistance_ohm",
                                          reference.RESISTANCE_VS_PRESSURE, p.table),
            "eq19_ratio_ohm_per_deg": p.ratio_ohm_per_deg, "eq19_ratio_se": p.ratio_se,
            "eq19_reference": reference.EQ19_SLOPE,
        }
    val = r.validation.to_dict(orient="records")
    corrected = [v for v in val if v["mapping"] != "factory"]
    best = min(corrected, key=lambda v: v["rmse_deg"])["mapping"] if corrected else "empirical"
    excluded = r.pairs.loc[~r.pairs["used"], ["trial", "image", "excluded"]].rename(columns={"excluded": "reason"})
    return _clean({
        "schema": SCHEMA, "schema_version": SCHEMA_VERSION, "flexcal_version": __version__,
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "inputs": inputs, "parameters": parameters,
        "pairs": {"total": len(r.pairs), "used": int(r.pairs["used"].sum()),
                  "excluded": excluded.to_dict(orient="records")},
        "models": models,
        "mappings": {name: m.to_dict() for name, m in r.mappings.items()},
        "recommended_mapping": best,
        "validation": val,
        "notes": r.notes,
    })


def write_json(data: dict, path) -> None:
    Path(path).write_text(json.dumps(data, indent=2, allow_nan=False) + "\n")


class Calibration:
    """A loaded calibration.json: its data and the mappings from resistance to corrected angle."""

    def __init__(self, data: dict, path: str = "calibration.json"):
        self.data = data
        self.path = path
        self.mappings = {name: mapping_from_dict(d) for name, d in data["mappings"].items()}
        self.recommended = data.get("recommended_mapping", "empirical")

    def mapping(self, name: str | None = None):
        name = name or self.recommended
        if name not in self.mappings:
            raise FlexcalError(f"{self.path}: no mapping {name!r}; it has {', '.join(self.mappings)}")
        return self.mappings[name]

    def angle_deg(self, resistance_ohm, *, mapping: str | None = None, extrapolate: bool = False):
        """Corrected angle (deg) of resistances (ohm) with the named (default: recommended) mapping."""
        return self.mapping(mapping).angle_deg(resistance_ohm, extrapolate=extrapolate)


def load(path) -> Calibration:
    """Load a calibration.json written by ``flexcal calibrate``."""
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise FlexcalError(f"{path}: no such file; give the calibration.json that calibrate wrote") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise FlexcalError(f"{path}: not a JSON file ({e}); give the calibration.json that calibrate wrote") from None
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise FlexcalError(f"{path}: not a flexcal calibration (no \"schema\": \"{SCHEMA}\")")
    if data.get("schema_version") != SCHEMA_VERSION:
        raise FlexcalError(f"{path}: schema version {data.get('schema_version')} but this flexcal reads "
                           f"{SCHEMA_VERSION}; use the flexcal version that wrote it ({data.get('flexcal_version')})")
    return Calibration(data, str(path))


def _c_float(x: float) -> str:
    """A C float literal (always with a decimal point or exponent before the f suffix)."""
    t = f"{float(x):.8g}"
    return (t if ("." in t or "e" in t) else t + ".0") + "f"


def header_text(data: dict, *, table_points: int = 32) -> str:
    """flexcal_calibration.h: the recommended mapping as a lookup table plus the empirical line.

    The table (resistance ascending -> corrected angle) works for either mapping; the
    inline function interpolates it and clamps outside the calibrated range.
    """
    cal = Calibration(data)
    m = cal.mapping()
    lo, hi = m.angle_range_deg
    angles = np.linspace(lo, hi, table_points)
    r = m.resistance_ohm(angles)
    emp = cal.mapping("empirical")

    def arr(v):
        return ", ".join(_c_float(x) for x in v)

    val = {v["mapping"]: v for v in data.get("validation", [])}.get(cal.recommended, {})
    return f"""/* flexcal_calibration.h -- generated by flexcal {data.get('flexcal_version')} on {data.get('created')}.
 * Do not edit: re-run `flexcal calibrate`. Mapping: {cal.recommended}
 * ({val.get('validation', 'not validated')}: RMSE {val.get('rmse_deg', float('nan')):.2f} deg,
 * max {val.get('max_abs_deg', float('nan')):.2f} deg). Valid for {lo:.1f} ... {hi:.1f} deg,
 * {r.min():.0f} ... {r.max():.0f} ohm.
 */
#ifndef FLEXCAL_CALIBRATION_H
#define FLEXCAL_CALIBRATION_H

/* direct empirical fit (eq 17): resistance_ohm = SLOPE * angle_deg + OFFSET */
#define FLEXCAL_CAL_SLOPE_OHM_PER_DEG {_c_float(emp.slope_ohm_per_deg)}
#define FLEXCAL_CAL_OFFSET_OHM {_c_float(emp.offset_ohm)}

#define FLEXCAL_CAL_R_MIN_OHM {_c_float(r.min())}
#define FLEXCAL_CAL_R_MAX_OHM {_c_float(r.max())}
#define FLEXCAL_CAL_TABLE_N {table_points}
static const float flexcal_cal_table_r_ohm[FLEXCAL_CAL_TABLE_N] = {{{arr(r)}}};
static const float flexcal_cal_table_angle_deg[FLEXCAL_CAL_TABLE_N] = {{{arr(angles)}}};

/* corrected angle (deg) for a resistance (ohm), clamped to the calibrated range */
static inline float flexcal_cal_angle_deg(float r_ohm)
{{
    int i;
    if (r_ohm <= flexcal_cal_table_r_ohm[0]) return flexcal_cal_table_angle_deg[0];
    for (i = 1; i < FLEXCAL_CAL_TABLE_N; i++) {{
        if (r_ohm <= flexcal_cal_table_r_ohm[i]) {{
            float f = (r_ohm - flexcal_cal_table_r_ohm[i - 1])
                      / (flexcal_cal_table_r_ohm[i] - flexcal_cal_table_r_ohm[i - 1]);
            return flexcal_cal_table_angle_deg[i - 1]
                   + f * (flexcal_cal_table_angle_deg[i] - flexcal_cal_table_angle_deg[i - 1]);
        }}
    }}
    return flexcal_cal_table_angle_deg[FLEXCAL_CAL_TABLE_N - 1];
}}

#endif /* FLEXCAL_CALIBRATION_H */
"""
