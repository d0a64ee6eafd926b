"""Reference angle tables: ImageJ Results exports and plain image,angle_deg CSVs.

ImageJ's angle tool reports the interior angle at the vertex; flexcal's bend angle is
its supplement (bend = 180 - interior). Results tables come as .csv (commas) or .txt
(tabs), with or without the blank-headed row-number column, with or without a Label
column. A plain CSV with ``image,angle_deg`` columns is taken as bend angles already.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from flexcal.errors import FlexcalError


def read_reference(path) -> pd.DataFrame:
    """Read a reference table; returns columns ``image`` (None when there is no label) and
    ``angle_deg`` (bend), one row per measurement, in file order, plus ``source``."""
    path = Path(path)
    if not path.is_file():
        raise FlexcalError(f"{path}: no such reference file; give an ImageJ Results .csv/.txt or an image,angle_deg CSV")
    text = path.read_text(encoding="utf-8-sig", errors="replace")
    sep = "\t" if path.suffix.lower() == ".txt" or text.split("\n", 1)[0].count("\t") > 0 else ","
    try:
        df = pd.read_csv(path, sep=sep, encoding="utf-8-sig")
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        raise FlexcalError(f"{path}: cannot read it as a table ({e}); export the Results window as .csv or .txt") from None
    df.columns = [str(c).strip() for c in df.columns]
    cols = {c.lower(): c for c in df.columns}
    if "angle_deg" in cols:
        image = df[cols["image"]].astype(str) if "image" in cols else None
        out = pd.DataFrame({"image": image, "angle_deg": pd.to_numeric(df[cols["angle_deg"]], errors="coerce")})
        out["source"] = "bend"
    elif "angle" in cols:
        interior = pd.to_numeric(df[cols["angle"]], errors="coerce")
        if (interior.abs() > 180).any():
            raise FlexcalError(f"{path}: the Angle column has values beyond 180 deg; is this an angle-tool export?")
        label = df[cols["label"]].astype(str) if "label" in cols else None
        out = pd.DataFrame({"image": label, "angle_deg": 180.0 - interior})
        out["source"] = "imagej_interior"
    else:
        raise FlexcalError(f"{path}: no Angle or angle_deg column (found {', '.join(df.columns)}); "
                           "measure with ImageJ's angle tool or give image,angle_deg")
    bad = out["angle_deg"].isna()
    if bad.any():
        first = int(bad.idxmax()) + 2   # header is line 1
        raise FlexcalError(f"{path}, line {first}: the angle is not a number; fix or delete that row")
    if out["image"] is None or out["image"].isna().all():
        out["image"] = None
    return out.reset_index(drop=True)
