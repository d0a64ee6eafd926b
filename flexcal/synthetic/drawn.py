"""A bent finger drawn another way: a check that vision is not tuned to ``render.py``.

``draw_finger(angle_deg)`` shares nothing with ``render_finger`` but the angle
convention: no anatomy table, no sensor model, no platform or wall presets. The hand is
a thick capsule running off the picture, the finger a tapered capsule from the knuckle
(the back of hand and finger in line, the palm thicker), shaded brighter along its middle
and lit from one side, with a nail at the tip and, sometimes, a dark strip along its back
(a sensor) and a table of another colour under the hand. Skin is any tone from pale to
dark, or a glove of any colour; the background any colour, with a gradient and blotches;
any roll, either side for the palm; optical blur, noise and JPEG; ``cluttered`` adds a
striped background, the middle finger behind the index and the sensor's lead. The vision
method was never shown these drawings while it was built; ``benchmarks/vision.py
--suites drawn,cluttered`` measures it on them.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

_SUB = 16   # drawing at 1/16 px (cv2 shift=4)


@dataclass
class DrawnTruth:
    """What was drawn: the bend (0 = straight, flexion positive), the knuckle (the
    centre of the finger's base, on its axis; the hand's axis runs nearer the palm, as
    the hand is thicker) and the drawing's random draws."""

    angle_deg: float
    vertex_xy: np.ndarray
    params: dict

    def as_dict(self) -> dict:
        return {"angle_deg": float(self.angle_deg), "vertex_x": float(self.vertex_xy[0]),
                "vertex_y": float(self.vertex_xy[1]), **self.params}


def _fix(p):
    return tuple(int(v) for v in np.round(np.asarray(p) * _SUB))


def _capsule(mask, a, b, ra, rb):
    """A filled capsule from a (radius ra) to b (radius rb), antialiased."""
    u = (b - a) / np.hypot(*(b - a))
    n = np.array([-u[1], u[0]])
    quad = np.array([a + n * ra, b + n * rb, b - n * rb, a - n * ra])
    cv2.fillPoly(mask, [np.round(quad * _SUB).astype(np.int32)], 255, cv2.LINE_AA, shift=4)
    for c, r in ((a, ra), (b, rb)):
        cv2.circle(mask, _fix(c), int(round(r * _SUB)), 255, -1, cv2.LINE_AA, shift=4)


def _unit(rad):
    return np.array([np.cos(rad), np.sin(rad)])


def draw_finger(angle_deg: float, *, shape=(960, 1280), rng=None, cluttered=False) -> tuple[np.ndarray, DrawnTruth]:
    """A BGR uint8 photo-like drawing of a finger bent by ``angle_deg`` at the knuckle.

    ``cluttered`` adds, each at random, a striped background, the middle finger behind
    the index (bent further) and the sensor's lead running off the picture; the plain
    drawing of the same ``rng`` is otherwise the same.
    """
    rng = np.random.default_rng(rng)
    # the clutter's own stream: a plain drawing's draws do not depend on it
    more = np.random.default_rng(rng.bit_generator.jumped())
    stripes = other_finger = lead = False
    if cluttered:
        stripes, other_finger, lead = (bool(v) for v in more.random(3) < (0.4, 0.4, 0.5))
    h, w = shape
    width = rng.uniform(0.04, 0.075) * max(h, w)      # the finger's width at the knuckle, px
    r0, r_tip = width / 2, width / 2 * rng.uniform(0.78, 0.9)
    length = width * rng.uniform(5.0, 6.5)            # knuckle to tip
    r_hand = r0 * rng.uniform(1.15, 1.7)               # the hand's half thickness
    roll = rng.uniform(0, 2 * np.pi)
    palm_side = int(rng.choice([-1, 1]))               # which side of the hand the palm is (mirroring)
    u_hand = _unit(roll)                               # the hand's direction, towards the knuckle
    to_palm = palm_side * np.array([-u_hand[1], u_hand[0]])
    u_finger = _unit(roll + palm_side * np.radians(angle_deg))
    knuckle = (np.array([w, h]) / 2 - u_finger * length * 0.45
               + rng.uniform(-0.08, 0.08, 2) * [w, h])
    tip = knuckle + u_finger * length
    hand_end = knuckle + to_palm * (r_hand - r0)       # backs in line, the palm thicker
    mask = np.zeros((h, w), np.uint8)
    _capsule(mask, hand_end - u_hand * 4 * max(h, w), hand_end, r_hand, r_hand)
    _capsule(mask, knuckle, tip, r0, r_tip)
    alpha = mask.astype(np.float32)[..., None] / 255
    behind = np.zeros((h, w), np.uint8)
    if other_finger:
        # the middle finger: from beside the knuckle, nearer the palm, bent further
        k2 = knuckle + to_palm * width * more.uniform(0.3, 0.6) - u_hand * width * more.uniform(0.0, 0.3)
        u2 = _unit(roll + palm_side * np.radians(angle_deg + more.uniform(15, 45)))
        _capsule(behind, k2, k2 + u2 * length * more.uniform(0.9, 1.05), r0 * 0.95, r_tip * 0.95)
        behind[mask > 127] = 0
    a_behind = behind.astype(np.float32)[..., None] / 255

    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    wall = rng.uniform(50, 235, 3)
    slope = rng.normal(size=2) * 0.15 / max(h, w)
    blotches = cv2.resize(rng.normal(size=(h // 64 + 2, w // 64 + 2)).astype(np.float32), (w, h),
                          interpolation=cv2.INTER_CUBIC)
    img = wall * (1 + (xx - w / 2) * slope[0] + (yy - h / 2) * slope[1] + 0.04 * blotches)[..., None]
    if stripes:     # wood grain, a fabric or a striped wall
        theta, period = more.uniform(0, np.pi), more.uniform(8, 60)
        img *= (1 + more.uniform(0.05, 0.15) * np.sin(2 * np.pi * (xx * np.cos(theta) + yy * np.sin(theta)) / period))[..., None]
    table = bool(rng.random() < 0.5)
    if table:
        side = to_palm if rng.random() < 0.7 else -to_palm
        beyond = (xx - hand_end[0]) * side[0] + (yy - hand_end[1]) * side[1] - r_hand * rng.uniform(1.2, 3.0)
        img[beyond > 0] = rng.uniform(40, 240, 3)
    shadow = cv2.warpAffine(cv2.GaussianBlur(np.maximum(alpha, a_behind)[..., 0], (0, 0), width * 0.4),
                            np.float32([[1, 0, to_palm[0] * width * 0.3], [0, 1, to_palm[1] * width * 0.3]]), (w, h))
    img *= (1 - 0.35 * rng.uniform(0.3, 1.0) * shadow)[..., None]

    glove = bool(rng.random() < 0.25)
    if glove:
        skin = rng.uniform(30, 230, 3)
    else:
        hsv = np.uint8([[[rng.uniform(4, 14), rng.uniform(70, 150), rng.uniform(0.25, 0.95) * 255]]])
        skin = cv2.cvtColor(hsv, cv2.COLOR_HSV2BGR)[0, 0].astype(float)
    depth = np.clip(cv2.distanceTransform((mask > 127).astype(np.uint8), cv2.DIST_L2, 5) / (0.9 * r0), 0, 1)
    across = np.clip(((xx - knuckle[0]) * to_palm[0] + (yy - knuckle[1]) * to_palm[1]) / (2 * r_hand), -1, 1)
    light = rng.uniform(-1, 1)
    shade = (0.62 + 0.38 * np.sqrt(depth)) * (1 - 0.15 * light * across)
    if other_finger:
        d2 = np.clip(cv2.distanceTransform((behind > 127).astype(np.uint8), cv2.DIST_L2, 5) / (0.9 * r0), 0, 1)
        img = img * (1 - a_behind) + (skin * 0.85 * (0.62 + 0.38 * np.sqrt(d2))[..., None]) * a_behind
    img = img * (1 - alpha) + (skin * shade[..., None]) * alpha

    strip = bool(rng.random() < 0.5)
    if strip:
        # a dark strip on the back of hand and finger, round the knuckle
        finger_palm = palm_side * np.array([-u_finger[1], u_finger[0]])
        back = [hand_end - u_hand * length * 1.2 - to_palm * (r_hand - 1), knuckle - to_palm * (r0 - 1)]
        back += [knuckle + u_finger * length * t - finger_palm * (r0 + (r_tip - r0) * t - 1) for t in (0.0, 0.75)]
        cv2.polylines(img, [np.round(np.array(back) * _SUB).astype(np.int32)], False, rng.uniform(20, 70, 3).tolist(),
                      max(2, int(round(0.1 * width))), cv2.LINE_AA, shift=4)
    if lead:
        # the sensor's lead: from the back of the hand, curving off the picture
        start = hand_end - u_hand * length * more.uniform(0.3, 0.9) - to_palm * r_hand
        away = _unit(more.uniform(0, 2 * np.pi)) * 2 * max(h, w)
        bend = -to_palm * max(h, w) * more.uniform(0.1, 0.5)
        q = np.linspace(0, 1, 60)[:, None]
        curve = (1 - q) ** 2 * start + 2 * q * (1 - q) * (start + bend) + q ** 2 * (start + away)
        cv2.polylines(img, [np.round(curve * _SUB).astype(np.int32)], False, more.uniform(10, 60, 3).tolist(),
                      max(2, int(round(more.uniform(0.05, 0.1) * width))), cv2.LINE_AA, shift=4)
    nail = np.zeros((h, w), np.uint8)
    cv2.ellipse(nail, _fix(tip - u_finger * r_tip * 0.9 - to_palm * r_tip * 0.35),
                (int(r_tip * _SUB), int(r_tip * 0.45 * _SUB)), float(np.degrees(np.arctan2(*u_finger[::-1]))),
                0, 360, 255, -1, cv2.LINE_AA, shift=4)
    a_nail = (nail.astype(np.float32)[..., None] / 255) * alpha * (0.0 if glove else 0.6)
    img = img * (1 - a_nail) + np.array([200.0, 205.0, 235.0]) * a_nail

    img = cv2.GaussianBlur(img.astype(np.float32), (0, 0), rng.uniform(0.7, 1.6))
    img += rng.normal(0, rng.uniform(1, 4), img.shape).astype(np.float32)
    quality = int(rng.integers(80, 96))
    _, buf = cv2.imencode(".jpg", np.clip(img, 0, 255).astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, quality])
    params = {"finger_width_px": float(width), "length_widths": float(length / width),
              "hand_to_finger": float(r_hand / r0), "roll_deg": float(np.degrees(roll) % 360),
              "palm_side": palm_side, "glove": glove, "table": table, "strip": strip, "jpeg_quality": quality,
              "stripes": stripes, "other_finger": other_finger, "lead": lead}
    return cv2.imdecode(buf, cv2.IMREAD_COLOR), DrawnTruth(float(angle_deg), knuckle, params)
