"""Method ``markers``: the bend from three coloured dots stuck on the finger (proximal,
joint, distal), found as round, strongly coloured blobs that differ in colour from all
round them (``find_markers``); the joint dot is the one opposite the triangle's longest
side."""

from __future__ import annotations

import cv2
import numpy as np

from flexcal.vision.measurement import AngleMeasurement, Arm, failed
from flexcal.vision.segment import box

MAX_DOT_AREA = 0.002      # a marker dot covers at most this share of the picture
DOT_STANDS_OUT = 30       # ... and this far in colour (CIELAB a*b*, 8 bit) from its surroundings


def find_markers(bgr, *, min_saturation=120, max_dots=12):
    """Centres (x, y) and radii of small, round, strongly coloured dots that stand out
    in colour from what they are stuck on.

    A dot is strongly coloured (HSV saturation at least ``min_saturation``) and its
    colour (CIELAB a*, b*) is at least ``DOT_STANDS_OUT`` from the mean colour around it
    (over three of the largest dot's widths): skin can be saturated itself (tanned skin
    reaches 110-140 of 255 in HSV) and so can a glove, and a saturation threshold alone
    joins the dots to the finger. Of the round blobs so found, a dot differs as much from
    nearly all round it (a ring of 1.5 to 2.5 radii): a corner of a poster or of a
    cutting mat does not.
    """
    h0, w0 = bgr.shape[:2]
    hsv = cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV)
    lab = cv2.cvtColor(bgr, cv2.COLOR_BGR2LAB)
    ab = lab[..., 1:]
    k = int(3 * 2 * np.sqrt(MAX_DOT_AREA * h0 * w0 / np.pi)) | 1
    # (a* and b* only, in 8 bit and integers, with OpenCV's own operations: a float
    # colour image, or numpy's, costs several times as much)
    squares = []
    for c in cv2.split(lab)[1:]:
        d = cv2.absdiff(c, cv2.blur(c, (k, k), borderType=cv2.BORDER_REFLECT))
        squares.append(cv2.multiply(d, d, dtype=cv2.CV_32S))
    stands_out = cv2.compare(cv2.add(*squares), DOT_STANDS_OUT ** 2, cv2.CMP_GE)
    sat = cv2.bitwise_and(cv2.inRange(hsv, (0, min_saturation, 60), (255, 255, 255)), stands_out)
    if not cv2.countNonZero(sat):
        return []
    # (the rest only where there is any: a box round it, with room for the opening)
    ys, xs = box(sat, 2)
    oy, ox = ys.start, xs.start
    # JPEG's colour noise in dark skin next to a dot stands out too: specks off
    sat = cv2.morphologyEx(sat[ys, xs], cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3)))
    _, comp, stats, _ = cv2.connectedComponentsWithStats(sat, connectivity=8)
    dots = []
    min_area = max(6, 1e-5 * h0 * w0)
    # blobs of a dot's size, about as wide as high, filling a disc (1 for a disc, 1.27
    # for a square) and not too small: all pieces at once (a wall can hold hundreds)
    area, wide, high = (stats[:, c].astype(float) for c in (cv2.CC_STAT_AREA, cv2.CC_STAT_WIDTH, cv2.CC_STAT_HEIGHT))
    fill = area / (np.pi / 4 * wide * high)
    aspect = wide / np.maximum(high, 1)
    round_dot = ((area >= min_area) & (area <= MAX_DOT_AREA * h0 * w0) & (aspect > 0.75) & (aspect < 1.33)
                 & (fill > 0.85) & (fill < 1.12) & (np.minimum(wide, high) >= 0.008 * min(h0, w0)))
    for i in np.nonzero(round_dot[1:])[0] + 1:
        a, bw, bh = stats[i, cv2.CC_STAT_AREA], stats[i, cv2.CC_STAT_WIDTH], stats[i, cv2.CC_STAT_HEIGHT]
        # the centroid of the saturation-weighted blob is sub-pixel
        x0, y0 = stats[i, cv2.CC_STAT_LEFT], stats[i, cv2.CC_STAT_TOP]
        blob = comp[y0:y0 + bh, x0:x0 + bw] == i
        x0, y0 = x0 + ox, y0 + oy          # (in the picture)
        patch = blob * hsv[y0:y0 + bh, x0:x0 + bw, 1].astype(float)
        yy, xx = np.mgrid[0:bh, 0:bw]
        cx, cy = (patch * xx).sum() / patch.sum() + x0, (patch * yy).sum() / patch.sum() + y0
        r = np.sqrt(a / np.pi)
        ya, yb = max(0, int(cy - 2.5 * r)), min(h0, int(cy + 2.5 * r) + 2)
        xa, xb = max(0, int(cx - 2.5 * r)), min(w0, int(cx + 2.5 * r) + 2)
        d2 = (np.arange(ya, yb)[:, None] - cy) ** 2 + (np.arange(xa, xb)[None, :] - cx) ** 2
        ring = ab[ya:yb, xa:xb][(d2 >= (1.5 * r) ** 2) & (d2 <= (2.5 * r) ** 2)].astype(float)
        own = np.median(ab[y0:y0 + bh, x0:x0 + bw][blob], axis=0)
        if len(ring) and np.percentile(np.hypot(*(ring - own).T), 10) < DOT_STANDS_OUT:
            continue
        dots.append((cx, cy, r))
    return dots[:max_dots]


def measure_markers(bgr) -> AngleMeasurement:
    """The bend from three marker dots (``find_markers``): the joint dot is the one
    opposite the triangle's longest side; failed unless exactly three, alike in size."""
    dots = find_markers(bgr)
    if len(dots) != 3:
        return failed(f"found {len(dots)} marker dots, need exactly 3 (proximal, joint, distal)", "markers")
    p = np.array([d[:2] for d in dots])
    radii = np.array([d[2] for d in dots])
    if radii.max() > 1.5 * radii.min():
        return failed("the three coloured dots differ in size; they are not a marker set", "markers")
    r = radii.mean()
    sides = [np.linalg.norm(p[(i + 1) % 3] - p[(i + 2) % 3]) for i in range(3)]
    j = int(np.argmax(sides))          # the joint dot is opposite the longest side
    a, b = p[(j + 1) % 3], p[(j + 2) % 3]
    va, vb = a - p[j], b - p[j]
    if min(np.linalg.norm(va), np.linalg.norm(vb)) < 4 * r:
        return failed("the marker dots are too close together to measure an angle", "markers")
    interior = np.degrees(np.arccos(np.clip(np.dot(va, vb) / np.linalg.norm(va) / np.linalg.norm(vb), -1, 1)))
    # centroid precision ~ 0.05 px per radius-normalised blob; propagate to the angle
    sig_pos = 0.1
    unc = float(np.degrees(np.sqrt(2) * sig_pos * np.sqrt(1 / np.linalg.norm(va) ** 2 + 1 / np.linalg.norm(vb) ** 2)))
    unc = float(np.hypot(unc, 0.1))
    # which arm is proximal is not known from dots alone; it does not change the angle
    return AngleMeasurement(
        angle_deg=float(180 - interior), angle_unc_deg=unc, confidence=0.95, status="ok", method="markers",
        vertex=(float(p[j][0]), float(p[j][1])),
        proximal=Arm(a, va / np.linalg.norm(va), float(np.linalg.norm(va))),
        distal=Arm(b, vb / np.linalg.norm(vb), float(np.linalg.norm(vb))),
        details=dict(dot_radius_px=float(r)),
    )
