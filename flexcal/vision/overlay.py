"""Drawings for people to check measurements: per-photo overlays and a contact sheet."""

from __future__ import annotations

import math
import textwrap

import cv2
import numpy as np

from flexcal.vision.measurement import AngleMeasurement, as_bgr8

_COLOURS = {"ok": (60, 200, 60), "low_confidence": (0, 190, 255), "failed": (40, 40, 230)}


def draw_overlay(image, m: AngleMeasurement) -> np.ndarray:
    """The photo with the two arms, the vertex and the angle drawn as ImageJ's angle tool
    shows them; for a refusal, the outline of what was taken for the hand and finger."""
    img = as_bgr8(image).copy()
    h, w = img.shape[:2]
    s = max(1.0, min(h, w) / 480)
    thick = max(1, int(round(2 * s)))
    col = _COLOURS.get(m.status, (200, 200, 200))
    if m.outline is not None and len(m.outline) > 1:
        pts = np.round(m.outline).astype(np.int32).reshape(-1, 1, 2)
        cv2.polylines(img, [pts], True, (0, 0, 0), thick + 2, cv2.LINE_AA)
        cv2.polylines(img, [pts], True, col, thick, cv2.LINE_AA)
    if m.proximal is not None and m.distal is not None and np.isfinite(m.vertex[0]):
        v = np.array(m.vertex, float)
        p_end = v + m.proximal.direction * m.proximal.length_px
        d_end = v + m.distal.direction * m.distal.length_px
        for end in (p_end, d_end):
            cv2.line(img, _pt(v), _pt(end), (0, 0, 0), thick + 2, cv2.LINE_AA)
            cv2.line(img, _pt(v), _pt(end), (0, 255, 255), thick, cv2.LINE_AA)
            cv2.circle(img, _pt(end), int(4 * s), (0, 255, 255), -1, cv2.LINE_AA)
        # the arc of the interior angle, as ImageJ draws it
        a0 = math.degrees(math.atan2(m.proximal.direction[1], m.proximal.direction[0]))
        a1 = math.degrees(math.atan2(m.distal.direction[1], m.distal.direction[0]))
        span = (a1 - a0 + 540) % 360 - 180
        r = int(0.25 * min(m.proximal.length_px, m.distal.length_px))
        cv2.ellipse(img, _pt(v), (r, r), 0, a0, a0 + span, (255, 0, 255), thick, cv2.LINE_AA)
        cv2.circle(img, _pt(v), int(5 * s), (255, 0, 255), -1, cv2.LINE_AA)
    label = (f"bend {m.angle_deg:.1f} +- {m.angle_unc_deg:.1f} deg  ({m.method}, conf {m.confidence:.2f})"
             if np.isfinite(m.angle_deg) else f"FAILED: {m.reason}")
    y = int(30 * s)
    for line in _fit_lines(label, w - int(20 * s), 0.7 * s):
        _text(img, line, (int(10 * s), y), 0.7 * s, col)
        y += int(30 * s)
    if m.status == "low_confidence":
        for line in _fit_lines(m.reason, w - int(20 * s), 0.5 * s):
            _text(img, line, (int(10 * s), y), 0.5 * s, col)
            y += int(22 * s)
    return img


def contact_sheet(images, labels, statuses=None, *, cols: int = 6, thumb_w: int = 320) -> np.ndarray:
    """One grid image of thumbnails with a caption under each (status-coloured frame)."""
    n = len(images)
    if n == 0:
        raise ValueError("contact_sheet needs at least one image")
    statuses = statuses or ["ok"] * n
    cols = max(1, min(cols, n))
    thumbs = []
    for img, lab, st in zip(images, labels, statuses):
        img = as_bgr8(img)
        th = int(round(img.shape[0] * thumb_w / img.shape[1]))
        t = cv2.resize(img, (thumb_w, max(1, th)), interpolation=cv2.INTER_AREA)
        thumbs.append((t, lab, st))
    cell_h = max(t.shape[0] for t, _, _ in thumbs) + 44
    rows = math.ceil(n / cols)
    sheet = np.full((rows * cell_h + 8, cols * (thumb_w + 8) + 8, 3), 255, np.uint8)
    for i, (t, lab, st) in enumerate(thumbs):
        r, c = divmod(i, cols)
        y, x = 8 + r * cell_h, 8 + c * (thumb_w + 8)
        sheet[y:y + t.shape[0], x:x + thumb_w] = t
        cv2.rectangle(sheet, (x - 3, y - 3), (x + thumb_w + 2, y + t.shape[0] + 2), _COLOURS.get(st, (128,) * 3), 3)
        for k, line in enumerate(_fit_lines(lab, thumb_w, 0.45, max_lines=2)):
            cv2.putText(sheet, line, (x, y + t.shape[0] + 18 + 16 * k), cv2.FONT_HERSHEY_SIMPLEX, 0.45,
                        (20, 20, 20), 1, cv2.LINE_AA)
    return sheet


def _fit_lines(text, width_px, scale, max_lines=None):
    """``text`` wrapped at spaces into lines no wider than ``width_px`` at this font scale;
    with ``max_lines``, what does not fit is cut at a word and marked with "..."."""
    thick = max(1, int(2 * scale))
    char_px = cv2.getTextSize("abcdefghij", cv2.FONT_HERSHEY_SIMPLEX, scale, thick)[0][0] / 10
    width = max(10, int(width_px / char_px))
    while True:   # characters differ in width: narrow the budget until every line fits
        lines = textwrap.wrap(text, width) or [""]
        if max_lines is not None and len(lines) > max_lines:
            lines = lines[:max_lines - 1] + [textwrap.shorten(" ".join(lines[max_lines - 1:]), width, placeholder="...")]
        widest = max(cv2.getTextSize(line, cv2.FONT_HERSHEY_SIMPLEX, scale, thick)[0][0] for line in lines)
        if widest <= width_px or width <= 10:
            return lines
        width -= 1


def _pt(p):
    return int(round(p[0])), int(round(p[1]))


def _text(img, text, org, scale, colour):
    """Text on a dark translucent band, readable on any wall (a green label on a green wall)."""
    thick = max(1, int(2 * scale))
    (tw, th), base = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, scale, thick)
    pad = max(2, int(4 * scale))
    x0, y0 = max(0, org[0] - pad), max(0, org[1] - th - pad)
    x1, y1 = min(img.shape[1], org[0] + tw + pad), min(img.shape[0], org[1] + base + pad)
    if x1 > x0 and y1 > y0:
        img[y0:y1, x0:x1] = (img[y0:y1, x0:x1] * 0.35).astype(np.uint8)
    cv2.putText(img, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, colour, thick, cv2.LINE_AA)
