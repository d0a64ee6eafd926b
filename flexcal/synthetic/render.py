"""Side-view photos of a finger wearing a flex sensor, with exact ground truth.

``render_finger(angle_deg)`` draws a hand resting palm-down on a platform, seen from the
side, with the index finger bent at the knuckle (MCP joint) over the platform's edge and a
flex-sensor strip on the back of the hand and finger spanning the bend. It returns the
photo and its truth: the bend angle, the vertex pixel (the joint centre) and points on
the two arms' axes (the hand's midline and the proximal phalanx's midline).

Geometry is built in millimetres in a canonical frame (joint centre at the origin, the
hand along -x, the finger along +x when straight, image y pointing down so flexion
turns the finger towards +y) and mapped to pixels by one similarity transform (scale,
camera roll, mirroring, translation). Every nuisance is a field of ``RenderParams``;
``difficulty`` presets draw them from a seeded generator and keyword arguments
override any of them.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields, replace

import cv2
import numpy as np

DIFFICULTIES = ("clean", "realistic", "hard")
GLOVES = (None, "latex", "nitrile_blue", "nitrile_purple", "black")
BACKGROUNDS = ("plain", "wood", "fabric", "clutter")
PLATFORMS = ("foam", "grey", "wood", "mat", "black")

# Skin tones, light to dark (BGR), after photographs of the Fitzpatrick range.
_SKIN_BGR = np.array([
    (196, 214, 246), (160, 184, 226), (122, 150, 203),
    (88, 118, 170), (60, 84, 126), (40, 55, 84),
], dtype=np.float32)
_GLOVE_BGR = {
    "latex": (178, 210, 226), "nitrile_blue": (200, 130, 60),
    "nitrile_purple": (170, 80, 110), "black": (38, 36, 36),
}
_PLATFORM_BGR = {
    "foam": (232, 234, 236), "grey": (128, 128, 124), "wood": (96, 142, 184),
    "mat": (70, 120, 40), "black": (40, 40, 42),
}

# Anatomy in millimetres (scaled by ``hand_size``).
_KNUCKLE_R = 11.0           # half thickness of the hand at the knuckle = knuckle radius
_PHALANX_L = (45.0, 26.0, 20.0)
_FINGER_W = (11.0, 9.5, 8.6, 7.6, 6.6)   # half widths: knuckle, flare end, PIP, DIP, tip
_FLARE_L = 14.0
_HAND_FLAT_L = 70.0         # length behind the knuckle over which the hand's back is flat
_SENSOR_SPAN = (-60.0, 44.0)  # path positions of the strip's ends (hand side negative)
_PALM_MM = (5.0, 10.0)      # the presets' palms: how much thicker a real hand is there than the finger at the knuckle


@dataclass(frozen=True)
class RenderParams:
    """Every nuisance of a render. Units: mm for anatomy, pixels for image effects."""

    skin_tone: float = 0.3            # 0 light ... 1 dark
    glove: str | None = None          # one of GLOVES
    background: str = "plain"         # one of BACKGROUNDS
    background_bgr: tuple = (205, 210, 214)
    platform: str = "foam"            # one of PLATFORMS
    roll_deg: float = 0.0             # camera roll
    mirror: bool = False              # True: finger points left
    scale: float = 1.0                # multiplier on the default 5 px/mm at 960 px
    offset_px: tuple = (0.0, 0.0)     # extra translation of the scene
    hand_size: float = 1.0            # anatomy multiplier
    finger_length: float = 1.0        # multiplier on the phalanges' lengths only (a slender finger > 1)
    palm_mm: float = 0.0              # extra thickness of the palm below the knuckle (real hands: ~5-10)
    pip_deg: float = 0.0              # second-joint (PIP) flexion; DIP follows at 0.7x
    light_deg: float = -120.0         # in-image direction towards the light
    shadow: float = 0.35              # strength of the soft shadow, 0...1
    exposure: float = 1.0             # global gain
    white_balance: tuple = (1.0, 1.0, 1.0)  # per-channel gains (B, G, R)
    vignette: float = 0.15
    noise_sigma: float = 1.0          # sensor noise, 8-bit levels
    blur_sigma: float = 0.0           # Gaussian blur, pixels
    jpeg_quality: int | None = None   # None: no compression
    sensor: bool = True               # draw the flex-sensor strip
    tape: bool = False                # tape bands holding the sensor
    cable: bool = False               # the sensor's lead, running off the frame
    other_finger: bool = False        # the middle finger, behind the index
    other_finger_deg: float = 15.0    # its extra flexion
    markers: bool = False             # three coloured dots: proximal, joint, distal
    texture_seed: int = 0             # seeds the textures (skin, background)


@dataclass
class FingerTruth:
    """What the renderer drew.

    Attributes
    ----------
    angle_deg : float
        Bend angle at the knuckle (0 = straight, flexion positive).
    vertex_xy : (2,) ndarray
        Pixel position of the joint centre, where the arms' axes meet.
    proximal_xy, distal_xy : (N, 2) ndarray
        Points on the hand's axis and on the proximal phalanx's axis, from the
        vertex outwards, in pixels.
    markers_xy : (3, 2) ndarray or None
        Centres of the proximal, joint and distal marker dots.
    mask : (H, W) bool ndarray
        Silhouette of the hand and index finger (sensor and tape included).
    px_per_mm : float
    params : RenderParams
    """

    angle_deg: float
    vertex_xy: np.ndarray
    proximal_xy: np.ndarray
    distal_xy: np.ndarray
    markers_xy: np.ndarray | None
    mask: np.ndarray
    px_per_mm: float
    params: RenderParams = field(repr=False)

    def as_dict(self) -> dict:
        """JSON-able summary (no mask)."""
        return {
            "angle_deg": float(self.angle_deg),
            "vertex_x": float(self.vertex_xy[0]), "vertex_y": float(self.vertex_xy[1]),
            "px_per_mm": float(self.px_per_mm),
            **{k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self.params).items()},
        }


# --------------------------------------------------------------------------- params

def sample_params(difficulty: str, rng: np.random.Generator) -> RenderParams:
    """Draw every nuisance for a difficulty preset from ``rng``."""
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"difficulty must be one of {', '.join(DIFFICULTIES)}, got {difficulty!r}")
    u = rng.uniform
    p = dict(
        skin_tone=float(u(0, 1)), mirror=bool(rng.random() < 0.5),
        light_deg=float(u(-160, -20)), texture_seed=int(rng.integers(0, 2**31 - 1)),
        background_bgr=tuple(float(c) for c in _random_wall(rng)),
        platform=str(rng.choice(PLATFORMS)), hand_size=float(u(0.9, 1.1)),
    )
    if difficulty == "clean":
        p.update(roll_deg=float(u(-3, 3)), scale=float(u(0.95, 1.05)), noise_sigma=float(u(0.5, 1.5)),
                 shadow=float(u(0.1, 0.3)), vignette=float(u(0, 0.1)),
                 offset_px=(float(u(-20, 20)), float(u(-20, 20))))
    elif difficulty == "realistic":
        p.update(
            glove=(str(rng.choice(GLOVES[1:])) if rng.random() < 0.25 else None),
            background=(str(rng.choice(BACKGROUNDS[1:])) if rng.random() < 0.5 else "plain"),
            roll_deg=float(u(-15, 15)), scale=float(u(0.8, 1.2)),
            offset_px=(float(u(-60, 60)), float(u(-40, 40))),
            pip_deg=(float(u(0, 20)) if rng.random() < 0.5 else 0.0),
            shadow=float(u(0.1, 0.5)), exposure=float(u(0.85, 1.15)),
            white_balance=tuple(float(g) for g in u(0.9, 1.1, 3)), vignette=float(u(0.05, 0.3)),
            noise_sigma=float(u(1.5, 4)), blur_sigma=float(u(0, 1.2)), jpeg_quality=int(rng.integers(75, 96)),
            tape=bool(rng.random() < 0.5), cable=bool(rng.random() < 0.7),
        )
    else:  # hard
        p.update(
            glove=(str(rng.choice(GLOVES[1:])) if rng.random() < 0.35 else None),
            background=str(rng.choice(BACKGROUNDS[1:])),
            roll_deg=float(u(-40, 40)), scale=float(u(0.6, 1.3)),
            offset_px=(float(u(-100, 100)), float(u(-60, 60))),
            pip_deg=(float(u(0, 45)) if rng.random() < 0.7 else 0.0),
            shadow=float(u(0.3, 0.7)), exposure=float(u(0.65, 1.3)),
            white_balance=tuple(float(g) for g in u(0.8, 1.2, 3)), vignette=float(u(0.2, 0.5)),
            noise_sigma=float(u(3, 9)), blur_sigma=float(u(0.5, 2.5)), jpeg_quality=int(rng.integers(40, 80)),
            tape=bool(rng.random() < 0.6), cable=bool(rng.random() < 0.8),
            other_finger=bool(rng.random() < 0.5), other_finger_deg=float(u(8, 35)),
        )
    # A real hand seen from the side is thicker than the finger by its palm (about 5-10
    # mm). Drawn from a stream of its own, seeded by the texture's seed, so that a render
    # with ``palm_mm=0`` given is otherwise the same photo (its noise, drawn from ``rng``
    # after these, included).
    p.update(palm_mm=float(np.random.default_rng([p["texture_seed"], 1]).uniform(*_PALM_MM)))
    return RenderParams(**p)


def _random_wall(rng):
    """A wall colour: mostly light neutrals, sometimes a colour, sometimes skin-like."""
    kind = rng.random()
    if kind < 0.6:
        v = rng.uniform(150, 240)
        return np.clip(v + rng.normal(0, 8, 3), 0, 255)
    if kind < 0.85:
        return rng.uniform(40, 220, 3)
    return np.clip(_SKIN_BGR[rng.integers(0, len(_SKIN_BGR))] + rng.normal(0, 25, 3), 0, 255)


def _check(angle_deg, shape, p: RenderParams):
    if not np.isfinite(angle_deg) or not 0 <= angle_deg <= 180:
        raise ValueError(f"angle_deg must be a bend angle within 0...180 degrees, got {angle_deg!r}")
    if len(shape) != 2 or min(shape) < 16:
        raise ValueError(f"shape must be (height, width) of at least 16 pixels each, got {shape!r}")
    checks = [
        ("noise_sigma", p.noise_sigma >= 0, "a non-negative number of 8-bit levels"),
        ("blur_sigma", p.blur_sigma >= 0, "a non-negative number of pixels"),
        ("scale", p.scale > 0, "a positive multiplier"),
        ("hand_size", p.hand_size > 0, "a positive multiplier"),
        ("finger_length", p.finger_length > 0, "a positive multiplier"),
        ("palm_mm", 0 <= p.palm_mm <= 40, "within 0 ... 40 mm"),
        ("skin_tone", 0 <= p.skin_tone <= 1, "within 0 (light) ... 1 (dark)"),
        ("shadow", 0 <= p.shadow <= 1, "within 0 ... 1"),
        ("vignette", 0 <= p.vignette <= 1, "within 0 ... 1"),
        ("exposure", p.exposure > 0, "a positive gain"),
        ("pip_deg", 0 <= p.pip_deg <= 110, "a flexion within 0 ... 110 degrees"),
        ("jpeg_quality", p.jpeg_quality is None or 1 <= p.jpeg_quality <= 100, "None or 1 ... 100"),
        ("glove", p.glove in GLOVES, f"one of {GLOVES}"),
        ("background", p.background in BACKGROUNDS, f"one of {BACKGROUNDS}"),
        ("platform", p.platform in PLATFORMS, f"one of {PLATFORMS}"),
    ]
    for name, ok, what in checks:
        if not ok:
            raise ValueError(f"{name} must be {what}, got {getattr(p, name)!r}")


# --------------------------------------------------------------------------- geometry

def _unit(deg):
    a = np.deg2rad(deg)
    return np.array([np.cos(a), np.sin(a)])


def _dorsal(deg):
    """Unit normal pointing to the back of the hand for a segment heading ``deg``."""
    a = np.deg2rad(deg)
    return np.array([np.sin(a), -np.cos(a)])


def _circle(c, r, n=48):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)])


def _quad(a, b, wa, wb):
    """Outline of a tapered segment from a (half width wa) to b (half width wb)."""
    d = (b - a) / np.linalg.norm(b - a)
    n = np.array([d[1], -d[0]])
    return np.array([a + n * wa, b + n * wb, b - n * wb, a - n * wa])


class _Finger:
    """Centre line and outline of one finger (mm, canonical frame)."""

    def __init__(self, angle_deg, pip_deg, size, origin=(0.0, 0.0), length=1.0):
        L = np.array(_PHALANX_L) * size * length
        w = np.array(_FINGER_W) * size
        self.size = size
        self.joint = np.asarray(origin, float)
        self.dirs = (angle_deg, angle_deg + pip_deg, angle_deg + pip_deg * 1.7)
        self.pip = self.joint + L[0] * _unit(self.dirs[0])
        self.dip = self.pip + L[1] * _unit(self.dirs[1])
        self.tip = self.dip + (L[2] - w[4]) * _unit(self.dirs[2])
        self.flare = self.joint + _FLARE_L * size * _unit(self.dirs[0])
        self.L, self.w = L, w

    def polygons(self):
        w = self.w
        return [
            _circle(self.joint, w[0]),
            _quad(self.joint, self.flare, w[0], w[1]),
            _quad(self.flare, self.pip, w[1], w[2]),
            _circle(self.pip, w[2] + 0.3 * self.size),
            _quad(self.pip, self.dip, w[2], w[3]),
            _circle(self.dip, w[3] + 0.2 * self.size),
            _quad(self.dip, self.tip, w[3], w[4]),
            _circle(self.tip, w[4]),
        ]

    def half_width(self, s):
        """Half width at path position s (mm from the joint along the finger)."""
        L, w = self.L, self.w
        xs = [0, _FLARE_L * self.size, L[0], L[0] + L[1], L.sum() - w[4]]
        return float(np.interp(s, xs, w))

    def point(self, s):
        """Point on the centre line at path position s >= 0."""
        if s <= self.L[0]:
            return self.joint + s * _unit(self.dirs[0])
        if s <= self.L[0] + self.L[1]:
            return self.pip + (s - self.L[0]) * _unit(self.dirs[1])
        return self.dip + (s - self.L[0] - self.L[1]) * _unit(self.dirs[2])

    def direction(self, s):
        return self.dirs[0] if s <= self.L[0] else self.dirs[1] if s <= self.L[0] + self.L[1] else self.dirs[2]


def _hand_polygon(size, palm=0.0):
    """The hand and forearm, palm flat on the platform (y = +R + palm), back rising to the
    wrist; a thicker palm (``palm`` mm) rounds off towards the finger's base."""
    R = _KNUCKLE_R * size
    xs = np.array([0, -_HAND_FLAT_L, -130, -220, -600]) * size
    top = np.array([-R, -R, -(R + 2.5 * size), -(R + 4.0 * size), -(R + 5.0 * size)])
    upper = np.column_stack([xs, top])
    if palm > 0:
        a = np.linspace(0, 90, 10)
        pad = np.column_stack([-2 * palm + 2 * palm * np.sin(np.deg2rad(a)), R + palm * np.cos(np.deg2rad(a))])
        lower = np.vstack([[xs[-1], R + palm], pad])
    else:
        lower = np.array([[xs[-1], R], [0, R]])
    return np.vstack([upper, lower])


def _hand_back_y(x, size):
    R = _KNUCKLE_R * size
    return -np.interp(-x, np.array([0, _HAND_FLAT_L, 130, 220, 600]) * size,
                      np.array([R, R, R + 2.5 * size, R + 4.0 * size, R + 5.0 * size]))


def _sensor_path(finger: _Finger, size, lift):
    """Points along the back of the hand, over the knuckle and along the finger."""
    R = _KNUCKLE_R * size
    s0, s1 = np.array(_SENSOR_SPAN) * size
    hand = [(x, _hand_back_y(x, size) - lift) for x in np.linspace(s0, 0, 16)]
    arc = [tuple((R + lift) * _unit(a)) for a in np.linspace(-90, -90 + finger.dirs[0], 24)]
    fing = []
    for s in np.linspace(0, s1, 24):
        d = finger.direction(s)
        fing.append(tuple(finger.point(s) + _dorsal(d) * (finger.half_width(s) + lift)))
    pts = np.array(hand + arc + fing)
    # The strip is stiff: it bridges the hollow where the finger narrows after the knuckle.
    return _convex_bridge(pts)


def _convex_bridge(pts):
    """Replace dips in the dorsal path by straight spans (the strip does not sag into them).

    Walks the path, each time jumping to the farthest of the next few points whose chord
    leaves no intermediate point on the dorsal side of it.
    """
    out = [pts[0]]
    i, n = 0, len(pts)
    while i < n - 1:
        best_j = i + 1
        for j in range(i + 1, min(n, i + 12)):
            v = pts[j] - pts[i]
            w = pts[i + 1:j] - pts[i]
            if np.all(v[0] * w[:, 1] - v[1] * w[:, 0] >= -1e-9):
                best_j = j
        out.append(pts[best_j])
        i = best_j
    return np.array(out)


def _resample(path, step):
    seg = np.linalg.norm(np.diff(path, axis=0), axis=1)
    s = np.concatenate([[0], np.cumsum(seg)])
    t = np.arange(0, s[-1], step)
    return np.column_stack([np.interp(t, s, path[:, 0]), np.interp(t, s, path[:, 1])]), s[-1]


def _band(path, half):
    """Outline of a band of half width ``half`` around a polyline."""
    d = np.gradient(path, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True) + 1e-12
    n = np.column_stack([d[:, 1], -d[:, 0]])
    return np.vstack([path + n * half, (path - n * half)[::-1]])


# --------------------------------------------------------------------------- raster

class _Canvas:
    def __init__(self, shape, A, t):
        self.h, self.w = shape
        self.A, self.t = A, t

    def px(self, pts):
        return np.asarray(pts, float) @ self.A.T + self.t

    def fill(self, img, polys, color):
        """Anti-aliased filled polygons (world mm) onto img (uint8, in place)."""
        # one call per polygon: a single fillPoly call would XOR overlapping polygons
        for p in polys:
            cv2.fillPoly(img, [np.round(self.px(p) * 16).astype(np.int32)], color, cv2.LINE_AA, 4)
        return img

    def alpha(self, polys):
        m = np.zeros((self.h, self.w), np.uint8)
        self.fill(m, polys, 255)
        return m.astype(np.float32) / 255.0

    def line(self, img, path, color, thickness_px):
        p = np.round(self.px(path) * 16).astype(np.int32)
        cv2.polylines(img, [p], False, color, max(1, int(round(thickness_px))), cv2.LINE_AA, 4)
        return img


def _bbox(alpha, margin=0):
    """Slices of the bounding box of alpha > 0 (grown by margin), or None if empty."""
    ys, xs = np.nonzero(alpha.any(axis=1))[0], np.nonzero(alpha.any(axis=0))[0]
    if len(ys) == 0:
        return None
    h, w = alpha.shape
    return (slice(max(0, ys[0] - margin), min(h, ys[-1] + 1 + margin)),
            slice(max(0, xs[0] - margin), min(w, xs[-1] + 1 + margin)))


def _over(img, alpha, colour, opacity=1.0):
    """Composite ``colour`` (BGR triple or an image like img) over img where alpha > 0, in place."""
    sl = _bbox(alpha)
    if sl is None:
        return img
    a = (alpha[sl] * np.float32(opacity))[..., None]
    c = colour[sl] if isinstance(colour, np.ndarray) and colour.ndim == 3 else np.float32(colour)
    img[sl] = img[sl] * (1 - a) + c * a
    return img


def _blur_large(a, sigma):
    """Gaussian blur with a large sigma, done at reduced resolution (shadows)."""
    f = max(1, int(sigma // 4))
    if f == 1:
        return cv2.GaussianBlur(a, (0, 0), sigma)
    h, w = a.shape[:2]
    small = cv2.resize(a, (max(1, w // f), max(1, h // f)), interpolation=cv2.INTER_AREA)
    small = cv2.GaussianBlur(small, (0, 0), sigma / f)
    return cv2.resize(small, (w, h), interpolation=cv2.INTER_LINEAR)


def _smooth_noise(shape, cell, rng, octaves=3):
    """Smooth value noise in [-1, 1] with features of about ``cell`` pixels."""
    h, w = shape
    out = np.zeros((h, w), np.float32)
    amp, total = 1.0, 0.0
    for _ in range(octaves):
        gh, gw = max(2, int(h / cell) + 2), max(2, int(w / cell) + 2)
        g = rng.uniform(-1, 1, (gh, gw)).astype(np.float32)
        out += amp * cv2.resize(g, (w, h), interpolation=cv2.INTER_CUBIC)
        total += amp
        amp *= 0.5
        cell = max(1.5, cell / 2)
    return np.clip(out / total, -1, 1)


def _background(shape, p: RenderParams, rng):
    h, w = shape
    base = np.array(p.background_bgr, np.float32)
    yy = np.arange(h, dtype=np.float32)[:, None]
    xx = np.arange(w, dtype=np.float32)[None, :]
    ramp = 1 + 0.08 * ((yy / h - 0.5) * np.cos(p.texture_seed % 7) + (xx / w - 0.5) * np.sin(p.texture_seed % 5))
    img = base[None, None, :] * ramp[..., None]
    img = np.ascontiguousarray(np.broadcast_to(img, (h, w, 3)))
    if p.background == "wood":
        a = rng.uniform(0, np.pi)
        warp = _smooth_noise(shape, 120, rng) * 25
        period = rng.uniform(10, 30)
        v = np.sin(2 * np.pi * (xx * np.cos(a) + yy * np.sin(a) + warp) / period)
        dark = base * np.float32(rng.uniform(0.6, 0.8))
        img = img + (dark - base)[None, None, :] * ((v[..., None] + 1) / 2) * 0.6
    elif p.background == "fabric":
        f = rng.uniform(3, 7)
        weave = np.sin(2 * np.pi * xx / f) * np.sin(2 * np.pi * yy / f)
        img = img * (1 + 0.06 * weave[..., None] + 0.05 * _smooth_noise(shape, 40, rng)[..., None])
    elif p.background == "clutter":
        for _ in range(int(rng.integers(4, 10))):
            blob = np.zeros(shape, np.float32)
            c = (int(rng.uniform(0, w)), int(rng.uniform(0, h)))
            ax = (int(rng.uniform(30, 250)), int(rng.uniform(20, 160)))
            if rng.random() < 0.5:
                cv2.ellipse(blob, c, ax, float(rng.uniform(0, 180)), 0, 360, 1.0, -1)
            else:
                cv2.rectangle(blob, (c[0] - ax[0], c[1] - ax[1]), (c[0] + ax[0], c[1] + ax[1]), 1.0, -1)
            blob = cv2.GaussianBlur(blob, (0, 0), rng.uniform(2, 10))
            col = rng.uniform(20, 235, 3).astype(np.float32)
            img = img * (1 - blob[..., None]) + col[None, None, :] * blob[..., None]
    img = img * (1 + 0.03 * _smooth_noise(shape, 60, rng)[..., None])
    return img


def _platform(canvas, shape, p: RenderParams, size, rng):
    R = _KNUCKLE_R * size + p.palm_mm * size    # the platform's top: where the palm rests
    edge = -(R + 3.5) * size
    far = 2000.0
    front = [np.array([[-far, R], [edge, R], [edge, far], [-far, far]])]
    top = [np.array([[-far, R - 2.5 * size], [edge - 1.0 * size, R - 2.5 * size], [edge, R], [-far, R]])]
    col = np.array(_PLATFORM_BGR[p.platform], np.float32)
    a_front, a_top = canvas.alpha(front), canvas.alpha(top)
    tex = np.ones(shape, np.float32) + 0.04 * _smooth_noise(shape, 30, rng)
    layer = col[None, None, :] * tex[..., None]
    if p.platform == "mat":  # a cutting mat: a grid of printed lines
        grid = np.zeros(shape, np.uint8)
        step = 10.0 * size
        for k in range(-200, 200):
            x = edge - k * step
            canvas.line(grid, np.array([[x, R], [x, far]]), 255, 1)
            y = R + k * step
            if y > R:
                canvas.line(grid, np.array([[-far, y], [edge, y]]), 255, 1)
        g = grid.astype(np.float32)[..., None] / 255.0
        layer = layer * (1 - g) + np.float32(190) * g
    top_col = np.clip(col * 1.15 + 10, 0, 255)
    return layer, a_front, top_col, a_top


def _shade(mask_a, p: RenderParams, r0_px, rng):
    """Cylinder-like shading from the silhouette: returns (diffuse, specular) maps."""
    binary = (mask_a > 0.5).astype(np.uint8)
    d = cv2.distanceTransform(binary, cv2.DIST_L2, 5).astype(np.float32)
    d = cv2.GaussianBlur(d, (0, 0), max(1.0, r0_px * 0.08))
    t = np.clip(d / (0.9 * r0_px), 0, 1)
    nz = np.sqrt(np.clip(1 - (1 - t) ** 2, 0, 1))
    gx = cv2.Sobel(d, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(d, cv2.CV_32F, 0, 1, ksize=3)
    gn = np.sqrt(gx * gx + gy * gy) + 1e-6
    nxy = np.sqrt(np.clip(1 - nz * nz, 0, 1))
    nx, ny = -gx / gn * nxy, -gy / gn * nxy
    el = np.deg2rad(55)
    L = np.array([np.cos(np.deg2rad(p.light_deg)) * np.sin(el), np.sin(np.deg2rad(p.light_deg)) * np.sin(el), np.cos(el)])
    lam = np.clip(nx * L[0] + ny * L[1] + nz * L[2], 0, 1)
    spec = lam ** (40 if p.glove else 12)
    return 0.32 + 0.68 * lam, spec, t


def render_finger(angle_deg: float, *, shape=(960, 1280), rng=None, difficulty: str = "clean", **params):
    """Render a side-view photo of a finger bent by ``angle_deg`` at the knuckle.

    Parameters
    ----------
    angle_deg : float
        Bend angle at the knuckle in degrees, 0 (straight) ... 180.
    shape : (int, int)
        Image (height, width) in pixels.
    rng : numpy.random.Generator or int or None
        Source of every random choice; an int seeds a new generator; None means seed 0
        (renders are deterministic unless asked otherwise).
    difficulty : {'clean', 'realistic', 'hard'}
        Preset from which the nuisances are drawn.
    **params
        Any field of ``RenderParams``, overriding the drawn value.

    Returns
    -------
    image : (H, W, 3) uint8 ndarray, BGR
    truth : FingerTruth

    Examples
    --------
    >>> img, truth = render_finger(40, shape=(480, 640), rng=1)
    >>> img.shape, round(truth.angle_deg)
    ((480, 640, 3), 40)
    """
    shape = tuple(int(s) for s in shape)
    rng = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(0 if rng is None else rng)
    unknown = set(params) - {f.name for f in fields(RenderParams)}
    if unknown:
        raise ValueError(f"unknown render parameter(s) {sorted(unknown)}; see flexcal.synthetic.RenderParams")
    p = replace(sample_params(difficulty, rng), **params)
    _check(angle_deg, shape if len(shape) == 2 else (0,), p)
    h, w = shape
    trng = np.random.default_rng(p.texture_seed)
    size = p.hand_size
    ppm = 5.0 * min(h, w) / 960.0 * p.scale

    # world (mm) -> pixels
    c, s = np.cos(np.deg2rad(p.roll_deg)), np.sin(np.deg2rad(p.roll_deg))
    A = ppm * np.array([[c, -s], [s, c]]) @ np.diag([-1.0 if p.mirror else 1.0, 1.0])
    centre_mm = (np.array([-40.0 * size, 0]) + 45.0 * size * _unit(angle_deg)) / 2
    t = np.array([w / 2, h / 2]) - A @ centre_mm + np.asarray(p.offset_px, float)
    cv_ = _Canvas(shape, A, t)

    finger = _Finger(angle_deg, p.pip_deg, size, length=p.finger_length)
    hand_poly = _hand_polygon(size, p.palm_mm * size)

    # --- scene layers (float BGR)
    img = _background(shape, p, trng)
    plat, a_front, top_col, a_top = _platform(cv_, shape, p, size, trng)

    body_polys = [hand_poly] + finger.polygons()
    a_body = cv_.alpha(body_polys)
    other = None
    if p.other_finger:
        other = _Finger(angle_deg + p.other_finger_deg, p.pip_deg * 1.2, size * 0.97,
                        origin=(2.0 * size, -1.5 * size), length=1.08)
        a_other = cv_.alpha(other.polygons())
    else:
        a_other = np.zeros(shape, np.float32)

    # soft shadow cast on the wall and platform, away from the light
    ld = np.deg2rad(p.light_deg)
    sh_off = -8.0 * ppm * np.array([np.cos(ld), np.sin(ld)])
    M = np.float32([[1, 0, sh_off[0]], [0, 1, sh_off[1]]])
    shadow = cv2.warpAffine(np.maximum(a_body, a_other), M, (w, h))
    shadow = _blur_large(shadow, 6.0 * ppm)
    img = img * (1 - p.shadow * shadow[..., None])
    plat = plat * (1 - p.shadow * 1.2 * _blur_large(a_body, 2.0 * ppm)[..., None])
    _over(img, a_front, plat)
    _over(img, a_top, top_col)

    # --- skin (or glove)
    if p.glove:
        base = np.array(_GLOVE_BGR[p.glove], np.float32)
    else:
        i = p.skin_tone * (len(_SKIN_BGR) - 1)
        k = min(int(i), len(_SKIN_BGR) - 2)
        base = _SKIN_BGR[k] * (1 - (i - k)) + _SKIN_BGR[k + 1] * (i - k)
    r0 = _FINGER_W[1] * size * ppm
    tex = 1 + (0.015 if p.glove else 0.05) * _smooth_noise(shape, 25, trng) \
        + (0.01 if p.glove else 0.025) * _smooth_noise(shape, 3, trng, octaves=1)

    def skin_layer(alpha, dim):
        col = np.zeros((h, w, 3), np.float32)
        sl = _bbox(alpha, margin=4)
        if sl is None:
            return col
        diffuse, spec, tdepth = _shade(alpha[sl], p, r0, trng)
        c = base[None, None, :] * (diffuse * tex[sl] * dim)[..., None]
        if not p.glove:  # skin reddens towards the silhouette (light scattered under it)
            c = c * (1 + 0.08 * (1 - tdepth)[..., None] * np.float32([-0.6, -0.2, 0.5]))
        col[sl] = c + np.float32(70.0 if p.glove else 25.0) * spec[..., None]
        return col

    if other is not None:
        _over(img, a_other, skin_layer(a_other, 0.78))
    skin = skin_layer(a_body, 1.0)

    # creases over the knuckle and the PIP joint, nail on the distal phalanx
    marks = np.zeros(shape, np.uint8)
    R = _KNUCKLE_R * size
    for k, rr in enumerate((0.55, 0.7, 0.85)):
        arc = np.array([rr * R * _unit(a) for a in np.linspace(-80, -95 + angle_deg * 0.9, 12)])
        cv_.line(marks, arc, 255, max(1, ppm * 0.35))
    for off in (-1.2, 0.0, 1.2):
        sp = finger.L[0] + off * size
        q = finger.point(sp)
        n = _dorsal(finger.direction(sp))
        cv_.line(marks, np.array([q + n * finger.w[2] * 0.35, q + n * finger.w[2] * 0.95]), 255, max(1, ppm * 0.3))
    m = cv2.GaussianBlur(marks.astype(np.float32) / 255, (0, 0), 0.6) * (0.08 if p.glove else 0.22)
    skin = skin * (1 - m[..., None])
    if not p.glove:
        d3 = finger.dirs[2]
        nd = _dorsal(d3)
        s_a, s_b = finger.L[0] + finger.L[1] + finger.L[2] * 0.3, finger.L.sum() - 0.3 * size
        ss = np.linspace(s_a, s_b, 10)
        outer = [finger.point(q) + nd * (finger.half_width(q) + 0.2 * size) for q in ss]
        inner = [finger.point(q) + nd * (finger.half_width(q) * 0.4) for q in ss[::-1]]
        a_nail = cv_.alpha([np.array(outer + inner)])
        a_nail = cv2.GaussianBlur(a_nail, (0, 0), 0.8) * a_body
        nail_col = base * 0.55 + np.float32([175, 185, 215]) * 0.45
        _over(skin, a_nail, nail_col * 1.05, 0.75)

    _over(img, a_body, skin)

    # --- the flex sensor strip, its connector and lead, tape bands
    body_extra = []
    if p.sensor:
        strip_half = 0.75 * size
        path = _sensor_path(finger, size, lift=strip_half * 0.9)
        path, _ = _resample(path, 0.5)
        strip = [_band(path, strip_half)]
        a_strip = cv_.alpha(strip)
        hi = cv_.alpha([_band(path + _path_normals(path) * strip_half * 0.6, strip_half * 0.25)])
        strip_col = np.float32([48, 46, 44])
        _over(img, a_strip, strip_col)
        img = img + 45.0 * (hi * a_strip)[..., None]
        body_extra += strip
        conn_x = _SENSOR_SPAN[0] * size
        y0 = _hand_back_y(conn_x, size)
        conn = [np.array([[conn_x - 9 * size, y0 - 4.2 * size], [conn_x + 0.5, y0 - 4.2 * size],
                          [conn_x + 0.5, y0], [conn_x - 9 * size, y0]])]
        a_conn = cv_.alpha(conn)
        _over(img, a_conn, (30, 30, 32))
        body_extra += conn
        if p.cable:
            p0 = np.array([conn_x - 9 * size, y0 - 2.0 * size])
            ctrl = [p0, p0 + np.array([-50, -4.0]) * size,
                    p0 + np.array([-120, trng.uniform(-40, 5)]) * size,
                    p0 + np.array([-400, trng.uniform(-150, -30)]) * size]
            tt = np.linspace(0, 1, 120)[:, None]
            bez = ((1 - tt) ** 3 * ctrl[0] + 3 * (1 - tt) ** 2 * tt * ctrl[1]
                   + 3 * (1 - tt) * tt ** 2 * ctrl[2] + tt ** 3 * ctrl[3])
            for off, col in ((-0.9, (40, 40, 200)), (0.9, (35, 35, 35))):
                wire = bez + _path_normals(bez) * off * size
                a_w = cv_.alpha([_band(wire, 0.85 * size)])
                _over(img, a_w, col)
    if p.tape:
        for sp in (-35.0 * size, 30.0 * size):
            if sp < 0:
                cx = np.array([sp, 0.0])
                d = np.array([1.0, 0.0])
                half = _KNUCKLE_R * size + 1.5 * size
            else:
                cx, d = finger.point(sp), _unit(finger.direction(sp))
                half = finger.half_width(sp) + 1.5 * size
            n = np.array([d[1], -d[0]])
            band = np.array([cx - d * 4 * size + n * half, cx + d * 4 * size + n * half,
                             cx + d * 4 * size - n * half, cx - d * 4 * size - n * half])
            a_t = cv_.alpha([band])
            tape_col = np.float32([215, 222, 226])
            _over(img, a_t, tape_col, 0.85)
            body_extra.append(band)

    # --- markers: dots on the arms' axes
    markers_xy = None
    if p.markers:
        pts = [np.array([-50.0 * size, 0.0]), np.array([0.0, 0.0]), finger.point(35.0 * size)]
        colours = [(40, 200, 40), (40, 40, 220), (220, 80, 30)]
        for q, col in zip(pts, colours):
            a_m = cv_.alpha([_circle(q, 3.0 * size, 40)])
            _over(img, a_m, col)
        markers_xy = cv_.px(np.array(pts))

    # --- camera: exposure, white balance, vignette, blur, noise, JPEG
    yy = np.arange(h, dtype=np.float32)[:, None]
    xx = np.arange(w, dtype=np.float32)[None, :]
    r2 = ((xx - w / 2) ** 2 + (yy - h / 2) ** 2) / ((w / 2) ** 2 + (h / 2) ** 2)
    gain = p.exposure * (1 - p.vignette * r2)
    img = img * gain[..., None] * np.float32(p.white_balance)[None, None, :]
    if p.blur_sigma > 0:
        img = cv2.GaussianBlur(img, (0, 0), p.blur_sigma)
    if p.noise_sigma > 0:
        img = img + rng.normal(0, p.noise_sigma, img.shape).astype(np.float32)
    out = np.clip(img + 0.5, 0, 255).astype(np.uint8)
    if p.jpeg_quality is not None:
        ok, buf = cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, int(p.jpeg_quality)])
        out = cv2.imdecode(buf, cv2.IMREAD_COLOR)

    mask = np.maximum(a_body, cv_.alpha(body_extra) if body_extra else 0) > 0.5
    prox = np.array([[-s_, 0.0] for s_ in np.linspace(0, _HAND_FLAT_L * size, 8)])
    dist = np.array([finger.point(s_) for s_ in np.linspace(0, finger.L[0], 8)])
    truth = FingerTruth(
        angle_deg=float(angle_deg), vertex_xy=cv_.px(np.zeros(2)), proximal_xy=cv_.px(prox),
        distal_xy=cv_.px(dist), markers_xy=markers_xy, mask=mask, px_per_mm=float(ppm), params=p,
    )
    return out, truth


def _path_normals(path):
    d = np.gradient(path, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True) + 1e-12
    return np.column_stack([d[:, 1], -d[:, 0]])
