"""Reading serial logs of every dialect people really have into the samples table.

``read_log(path)`` reads what our firmware and ``capture`` write, and also: raw Serial
Monitor pastes (``#`` or ``//`` comments, ``Resistance: 45000 ohms`` text, a partial
first line, blank lines, a value glued onto a comment line), CSV with or without a
header, ``;`` or tab separators, trailing separators, a UTF-8 byte-order mark, CRLF
line ends, a header unit mis-encoded as ``kÎ©``, resistance in kΩ or Ω, ADC-only logs,
device time, host time, both, or none.

The result is the serial samples table of DESIGN.md:
``t_s, t_host_s, t_device_ms, adc, resistance_ohm, angle_deg`` plus ``line`` (the
line of the file each sample came from) and any other columns as they were. What the
reader decided (units, time source, divider, lines it could not read) is in
``df.attrs["log"]``, a ``LogInfo``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from flexcal.divider import Divider, factory_angle_deg
from flexcal.errors import FlexcalError

SAMPLE_COLUMNS = ["t_s", "t_host_s", "t_device_ms", "adc", "resistance_ohm", "angle_deg"]

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_NUM_RE = re.compile(rf"^{_NUM}$")
_NAN_WORDS = {"nan", "inf", "-inf", "ovf", "-"}

# column names people use, lower case with units and punctuation removed
_SYNONYMS = {
    "t_s": {"t_s", "t", "time", "time_s", "seconds", "sec", "s", "timestamp", "elapsed", "elapsed_s"},
    "t_host_s": {"t_host_s", "host_s", "host_time", "host_time_s", "t_host", "pc_time", "received"},
    "t_device_ms": {"t_ms", "t_device_ms", "ms", "millis", "time_ms", "device_ms", "t_device", "device_time"},
    "adc": {"adc", "raw", "analog", "analogread", "a0", "a1", "a2", "counts", "adc_counts", "reading", "value"},
    "resistance_ohm": {"resistance_ohm", "resistance", "r", "r_ohm", "res", "ohms", "ohm", "flex_resistance",
                       "rflex", "r_flex", "resistance_kohm", "r_kohm", "kohm", "kohms"},
    "angle_deg": {"angle_deg", "angle", "deg", "degrees", "bend", "bend_deg", "theta", "flex_angle"},
}


@dataclass
class LogInfo:
    """What ``read_log`` found and decided, for reports and messages."""

    path: str
    dialect: str = ""
    resistance_unit: str = ""
    time_source: str = ""
    divider: Divider | None = None
    divider_source: str = ""
    angle_source: str = ""
    banner: list = field(default_factory=list)
    n_lines: int = 0
    n_samples: int = 0
    bad_lines: int = 0
    bad_examples: list = field(default_factory=list)   # (line number, text, reason)
    notes: list = field(default_factory=list)

    def summary(self) -> str:
        s = (f"{self.path}: {self.n_samples} samples ({self.dialect}); resistance {self.resistance_unit}; "
             f"time: {self.time_source}")
        if self.bad_lines:
            shown = "; ".join(f"line {n}: {reason}" for n, _, reason in self.bad_examples[:3])
            s += f"; {self.bad_lines} unreadable line(s) skipped ({shown})"
        return s


def _clean_name(name: str) -> tuple[str, str]:
    """Canonical key and unit text of a header field: 'Resistance (kÎ©)' -> ('resistance', 'kΩ')."""
    raw = name.strip().strip('"').strip("'")
    unit = ""
    m = re.search(r"[\(\[](.*?)[\)\]]", raw)
    if m:
        unit = m.group(1)
        raw = raw[:m.start()] + raw[m.end():]
    key = re.sub(r"[^0-9a-z_]+", "_", raw.lower().replace("Î©", "ohm").replace("Ω", "ohm").replace("ω", "ohm"))
    key = key.strip("_")
    return key, unit


def _unit_scale(text: str) -> float | None:
    """Ohms per unit for a resistance unit text (kΩ, kohm, Ω, MΩ, the mojibake 'kÎ©'), None if none."""
    t = text.replace("Î©", "Ω").replace("ω", "Ω").strip().lower()
    if re.search(r"(^|[^a-z])(k|kilo)\s*(Ω|ohm)", t) or t in ("k", "kohm", "kohms", "kΩ".lower()):
        return 1e3
    if re.search(r"(^|[^a-z])(m|mega)\s*(Ω|ohm)", t) and "mohm" not in t.replace("megaohm", ""):
        return 1e6
    if "Ω".lower() in t or "ohm" in t:
        return 1.0
    return None


def _canonical(key: str) -> str | None:
    for canon, names in _SYNONYMS.items():
        if key in names:
            return canon
    if key.startswith("resistance") or key.startswith("r_"):
        return "resistance_ohm"
    if key.startswith("angle"):
        return "angle_deg"
    return None


def _to_float(tok: str) -> float | None:
    t = tok.strip().strip('"')
    if t.lower() in _NAN_WORDS:
        return float("nan")
    if _NUM_RE.match(t):
        return float(t)
    return None


_LABEL_VALUE = re.compile(rf"([A-Za-z][A-Za-z0-9_ ]*?)\s*(?:\(([^)]*)\))?\s*[:=]\s*({_NUM}|nan)\s*([kKmM]?\s*(?:Ω|Î©|ohms?|Ohms?|OHMS?)|deg\w*|°|ms|s\b)?")
_GLUED = re.compile(r"^(.*?[A-Za-z.!?)\]>])(\d+(?:\.\d+)?)$")
_BARE = re.compile(rf"^({_NUM})\s*([kKmM]?\s*(?:Ω|Î©|ohms?|Ohms?|OHMS?))?$")
_TRAILING_COMMENT = re.compile(r"\s*(//|#).*$")


def _split(line: str, sep: str | None) -> list[str]:
    parts = line.split() if sep is None else line.split(sep)
    while parts and not parts[-1].strip():   # trailing separators
        parts.pop()
    return [p.strip() for p in parts]


def _guess_sep(lines: list[str]) -> str | None:
    """The separator of the data lines: the candidate giving one stable field count > 1."""
    best, best_score = None, 0.0
    for sep in ("\t", ";", ","):
        counts = [len(_split(s, sep)) for s in lines if sep in s]
        if not counts:
            continue
        mode = max(set(counts), key=counts.count)
        score = counts.count(mode) / len(lines) * (mode > 1)
        if score > best_score:
            best, best_score = sep, score
    if best is None and any(len(s.split()) > 1 for s in lines):
        return None  # whitespace
    return best if best is not None else ","


def read_log(path, *, divider: Divider | None = None, resistance_unit: str | None = None) -> pd.DataFrame:
    """Read a serial log into the samples table.

    Parameters
    ----------
    path : str or Path
        The log file.
    divider : Divider, optional
        The voltage divider, for logs with ADC counts but no resistance. Without it the
        firmware banner's ``divider:`` line is used if the log has one.
    resistance_unit : {"ohm", "kohm"}, optional
        Force the resistance unit instead of reading it from the header or magnitude.

    Returns
    -------
    DataFrame with ``t_s, t_host_s, t_device_ms, adc, resistance_ohm, angle_deg, line``
    (NaN where the log has no such quantity) and extra columns as found; file order.
    ``t_s`` is the best clock: ``t_s`` as written, else host time, else device time
    (ms / 1000), else NaN (row order only). ``df.attrs["log"]`` is a ``LogInfo``.

    Raises
    ------
    FlexcalError
        Missing or unreadable file, or no usable data (one line, naming the file).
    """
    path = Path(path)
    if not path.is_file():
        raise FlexcalError(f"{path}: no such log file; give the serial log (e.g. trial_01/serial.csv)")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    lines = text.splitlines()
    info = LogInfo(path=str(path), n_lines=len(lines))

    def bad(n, s, reason):
        info.bad_lines += 1
        if len(info.bad_examples) < 5:
            info.bad_examples.append((n, s[:60], reason))

    # pass 1: classify lines; collect comments, header, data candidates
    comments, header, data = [], None, []   # data: (line number, content)
    for n, line in enumerate(lines, start=1):
        s = line.strip().lstrip("\ufeff").strip()
        if not s:
            continue
        if s.startswith("#") or s.startswith("//"):
            body = s.lstrip("#/").strip()
            m = _GLUED.match(body)
            if m and len(re.sub(r"\D", "", m.group(2))) >= 3 and not re.search(r"[=:]\s*$", m.group(1)):
                comments.append(m.group(1))
                data.append((n, m.group(2)))      # a value glued onto a comment line
                info.notes.append(f"line {n}: took the value {m.group(2)} glued to the end of a comment")
            else:
                comments.append(body)
            continue
        s = _TRAILING_COMMENT.sub("", s) if re.match(rf"^\s*{_NUM}", s) else s
        tokens = re.split(r"[,;\t ]+", s.strip(",;\t "))
        numeric = sum(_to_float(t) is not None for t in tokens)
        if header is None and not data and numeric == 0 and not _LABEL_VALUE.search(s):
            header = (n, s)
            continue
        data.append((n, s))
    info.banner = comments
    if divider is None:
        for c in comments:
            d = Divider.from_banner(c)
            if d is not None:
                divider, info.divider_source = d, "firmware banner"
    elif divider is not None:
        info.divider_source = "given"
    info.divider = divider
    if not data:
        raise FlexcalError(f"{path}: no data lines found ({len(lines)} lines, all blank, comments or a header); "
                           "is this the serial log?")

    labelled = sum(bool(_LABEL_VALUE.search(s)) for _, s in data[:200]) > 0.5 * min(len(data), 200)
    rows, units = ([], {})
    if labelled:
        info.dialect = "labelled text (Serial Monitor)"
        for n, s in data:
            found = {}
            for label, unit_in_paren, num, unit in _LABEL_VALUE.findall(s):
                key = _canonical(_clean_name(label)[0])
                if key is None:
                    key = _clean_name(label)[0]
                u = unit or unit_in_paren
                if key == "resistance_ohm" and u:
                    units.setdefault("resistance_ohm", u)
                if key == "t_s" and u.strip() == "ms":
                    key = "t_device_ms"
                found[key] = float(num)
            bare = None if found else _BARE.match(s)
            if bare:   # a bare value among labelled lines (glued to a comment, or a partial line)
                found = {"resistance_ohm" if bare.group(2) else "value": float(bare.group(1))}
            if not found:
                bad(n, s, "no 'name: value' in it")
                continue
            found["line"] = n
            rows.append(found)
        keys = [k for r in rows for k in r if k != "line"]
        main = max(set(keys), key=keys.count) if keys else "resistance_ohm"
        for r in rows:
            if "value" in r and main != "value":
                r[main] = r.pop("value")
    else:
        sep = _guess_sep([s for _, s in data[:200]])
        info.dialect = {"\t": "tab-separated", ";": "semicolon-separated", ",": "comma-separated",
                        None: "whitespace-separated"}[sep]
        decimal_comma = sep in (";", "\t", None) and any(re.search(r"\d,\d", s) for _, s in data[:50])
        if header is not None:
            names = _split(header[1], sep)
            columns = []
            for name in names:
                key, unit = _clean_name(name)
                canon = _canonical(key)
                if canon == "resistance_ohm" and (unit or _unit_scale(name)):
                    units["resistance_ohm"] = unit or name
                if canon == "t_s" and (unit.strip().lower() == "ms" or key.endswith("_ms")):
                    canon = "t_device_ms"
                columns.append(canon or name.strip() or f"column_{len(columns) + 1}")
            info.dialect += " with header"
        else:
            columns = None
            info.dialect += ", no header"
        counts = []
        parsed = []
        for n, s in data:
            toks = _split(s, sep)
            vals = [_to_float(t.replace(",", ".") if decimal_comma else t) for t in toks]
            if any(v is None for v in vals):
                bad(n, s, "not a number in it")
                continue
            parsed.append((n, vals))
            counts.append(len(vals))
        if not parsed:
            raise FlexcalError(f"{path}: no line holds numbers ({info.bad_lines} unreadable lines, first: line "
                               f"{info.bad_examples[0][0]}); is this the serial log?")
        width = columns and len(columns) or max(set(counts), key=counts.count)
        if columns is None:
            columns = _guess_columns([v for _, v in parsed if len(v) == width], width)
            info.notes.append(f"no header: took the columns as {', '.join(columns)}")
        for i, (n, vals) in enumerate(parsed):
            if len(vals) != width:
                why = "partial first line" if i == 0 else f"{len(vals)} fields where the others have {width}"
                bad(n, lines[n - 1].strip(), why)
                continue
            rows.append({**dict(zip(columns, vals)), "line": n})

    df = pd.DataFrame(rows)
    if df.empty:
        raise FlexcalError(f"{path}: no usable samples ({info.bad_lines} unreadable lines); is this the serial log?")
    df = _drop_partial_first(df, info)
    _resolve_resistance(df, info, units, resistance_unit)
    if df["resistance_ohm"].isna().all() and "adc" in df:
        if divider is None:
            raise FlexcalError(f"{path}: the log has ADC counts but no resistance and no firmware banner; give the "
                               "divider (--r-fixed-ohm, and --vref-v/--adc-bits if not 5 V/10 bit)")
        df["resistance_ohm"] = divider.resistance_from_adc(df["adc"].to_numpy(float))
        info.resistance_unit = f"ohm, computed from ADC counts ({info.divider_source} divider: {divider.banner()})"
    if df["resistance_ohm"].isna().all():
        raise FlexcalError(f"{path}: found no resistance or ADC column (columns: {', '.join(map(str, df.columns[:-1]))});"
                           " name the columns in a header line, e.g. t_ms,adc,resistance_ohm,angle_deg")
    if "angle_deg" in df and df["angle_deg"].notna().any():
        info.angle_source = "firmware"
    else:
        df["angle_deg"] = factory_angle_deg(df["resistance_ohm"])
        info.angle_source = "factory mapping (R - 31250) / 577.9 applied by flexcal; the log has no angle"
    _resolve_time(df, info)
    info.n_samples = len(df)
    df = df[SAMPLE_COLUMNS + ["line"] + [c for c in df.columns if c not in SAMPLE_COLUMNS and c != "line"]]
    df = df.reset_index(drop=True)
    df.attrs["log"] = info
    return df


def _guess_columns(rows: list[list[float]], width: int) -> list[str]:
    """Names for headerless numeric columns, from what the values look like."""
    a = np.array(rows, float) if rows else np.zeros((0, width))
    if width == 4:
        return ["t_device_ms", "adc", "resistance_ohm", "angle_deg"]   # our firmware's protocol
    names: list[str] = []
    cols = list(range(width))
    if width >= 2 and len(a) > 1 and np.all(np.diff(a[:, 0]) >= 0) and np.ptp(a[:, 0]) > 0:
        integer = np.allclose(a[:, 0], np.round(a[:, 0]))
        names.append("t_device_ms" if integer else "t_s")
        cols = cols[1:]
    for c in cols:
        v = a[:, c]
        fin = v[np.isfinite(v)]
        if "resistance_ohm" not in names and fin.size and (np.median(fin) > 1023 or (
                c == cols[-1] and "adc" in names)):
            names.append("resistance_ohm")
        elif "adc" not in names and "resistance_ohm" not in names and fin.size and fin.min() >= 0 \
                and fin.max() <= 1023 and (len(cols) > 1 or np.allclose(fin, np.round(fin))):
            names.append("adc")
        elif "resistance_ohm" in names and "angle_deg" not in names:
            names.append("angle_deg")
        elif "resistance_ohm" not in names:
            names.append("resistance_ohm")
        else:
            names.append(f"column_{c + 1}")
    return names


def _drop_partial_first(df: pd.DataFrame, info: LogInfo) -> pd.DataFrame:
    """A Serial Monitor paste often starts mid-line: '95.2' of '45095.2'. Drop it when it
    is an order of magnitude off the next samples."""
    col = "resistance_ohm" if "resistance_ohm" in df else ("adc" if "adc" in df else None)
    if col is None or len(df) < 5:
        return df
    first, rest = df[col].iloc[0], df[col].iloc[1:21].median()
    if np.isfinite(first) and np.isfinite(rest) and rest > 0 and not 0.2 < first / rest < 5:
        info.bad_lines += 1
        info.bad_examples.insert(0, (int(df["line"].iloc[0]), str(first), "partial first line"))
        return df.iloc[1:].reset_index(drop=True)
    return df


def _resolve_resistance(df: pd.DataFrame, info: LogInfo, units: dict, forced: str | None) -> None:
    if "resistance_ohm" not in df:
        df["resistance_ohm"] = np.nan
        info.resistance_unit = "none in the log"
        return
    r = df["resistance_ohm"].astype(float)
    if forced is not None:
        if forced not in ("ohm", "kohm"):
            raise ValueError(f"resistance_unit must be 'ohm' or 'kohm', got {forced!r}")
        scale, why = (1e3 if forced == "kohm" else 1.0), "as given"
    elif "resistance_ohm" in units and _unit_scale(units["resistance_ohm"]) is not None:
        scale, why = _unit_scale(units["resistance_ohm"]), f"from the unit {units['resistance_ohm'].strip()!r}"
    else:
        med = np.nanmedian(r) if r.notna().any() else np.nan
        scale = 1e3 if np.isfinite(med) and med < 1_000 else 1.0
        why = f"from the magnitude (median {med:g})"
    df["resistance_ohm"] = r * scale
    info.resistance_unit = ("kΩ" if scale == 1e3 else "MΩ" if scale == 1e6 else "Ω") + f" in the log, {why}"


def _resolve_time(df: pd.DataFrame, info: LogInfo) -> None:
    for c in ("t_s", "t_host_s", "t_device_ms", "adc"):
        if c not in df:
            df[c] = np.nan
    if df["t_s"].notna().any():
        info.time_source = "t_s as written"
    elif df["t_host_s"].notna().any():
        df["t_s"] = df["t_host_s"]
        info.time_source = "host receive time"
    elif df["t_device_ms"].notna().any():
        df["t_s"] = df["t_device_ms"] / 1000.0
        info.time_source = "device time (ms / 1000)"
    else:
        info.time_source = "none: samples in row order only"
        return
    t = df["t_s"].to_numpy(float)
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        i = back[0] + 1
        info.notes.append(f"time goes backwards {back.size} time(s), first at line {int(df['line'].iloc[i])} "
                          f"({t[i]:g} s after {t[i - 1]:g} s): did the device reset?")


def parse_text_line(text: str) -> dict | None:
    """Values in one live line that is not the firmware protocol: ``Resistance: 45000 ohms``,
    ``ADC: 512``, or a bare number (a resistance; kΩ when below 1000). Keys are the samples
    table's columns; None when the line holds no value."""
    s = text.strip()
    found = {}
    for label, unit_in_paren, num, unit in _LABEL_VALUE.findall(s):
        key = _canonical(_clean_name(label)[0])
        if key is None:
            continue
        v = float(num)
        if key == "resistance_ohm":
            v *= _unit_scale(unit or unit_in_paren) or (1e3 if v < 1000 else 1.0)
        found[key] = v
    if not found:
        m = _BARE.match(s)
        if m:
            v = float(m.group(1))
            found["resistance_ohm"] = v * (_unit_scale(m.group(2) or "") or (1e3 if v < 1000 else 1.0))
    return found or None
