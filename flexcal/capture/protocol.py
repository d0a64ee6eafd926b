"""The firmware line protocol (DESIGN.md), written and read in one place.

115200 baud, lines end in ``\\r\\n``. Comment lines start with ``#`` (boot banner,
warnings); one header line ``t_ms,adc,resistance_ohm,angle_deg``; then one data line
per sample, e.g. ``123456,574.25,60123.4,48.21``. An open or shorted sensor gives
``nan`` resistance and angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

HEADER = "t_ms,adc,resistance_ohm,angle_deg"
COLUMNS = tuple(HEADER.split(","))
EOL = "\r\n"
BAUD = 115200


@dataclass(frozen=True)
class Sample:
    """One data line: device time (ms), ADC counts, resistance (ohm), firmware angle (deg)."""

    t_ms: int
    adc: float
    resistance_ohm: float
    angle_deg: float


@dataclass(frozen=True)
class Comment:
    """A ``#`` line, without the ``#`` and surrounding blanks."""

    text: str


@dataclass(frozen=True)
class Header:
    """The column header line."""

    columns: tuple[str, ...]


def _num(x: float, digits: int) -> str:
    return "nan" if not math.isfinite(x) else f"{x:.{digits}f}"


def format_sample(t_ms: int, adc: float, resistance_ohm: float, angle_deg: float) -> str:
    """One data line, without the line end."""
    return f"{int(t_ms)},{_num(adc, 2)},{_num(resistance_ohm, 1)},{_num(angle_deg, 2)}"


def format_comment(text: str) -> str:
    return f"# {text}"


def parse_line(line: str):
    """Parse one protocol line.

    Returns a ``Sample``, ``Comment`` or ``Header``; ``None`` for a blank line.
    Raises ``ValueError`` with the reason for anything else.
    """
    s = line.strip().lstrip("\ufeff")
    if not s:
        return None
    if s.startswith("#"):
        return Comment(s[1:].strip())
    fields = [f.strip() for f in s.split(",")]
    if tuple(f.lower() for f in fields) == COLUMNS:
        return Header(tuple(fields))
    if len(fields) != len(COLUMNS):
        raise ValueError(f"expected {len(COLUMNS)} comma-separated fields ({HEADER}), got {len(fields)}")
    try:
        t_ms = int(fields[0])
        adc, r, a = (float(f) for f in fields[1:])
    except ValueError:
        raise ValueError(f"not a number in {s!r}") from None
    return Sample(t_ms, adc, r, a)
