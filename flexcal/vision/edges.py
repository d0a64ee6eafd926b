"""Where the skin (or glove) ends, under whatever is stuck on the finger.

The silhouette's outline is the outline of the finger *and* of what lies on it: the
flex-sensor strip along the back, the tape bands holding it, the sensor's connector.
The strip is stiff and bridges the hollow behind the knuckle, so its outer edge is
not parallel to the bone, and tape bands stand off the skin on both sides: lines
fitted to that outline are tilted and uneven. The finger's own edge is where the
arm's own colour begins, looking inwards from the outline.

For each outline point the colour is sampled along the inward normal and compared
with the arm's core colour on that side (taken at a depth where nothing attached
reaches). Where the profile starts with a layer of another colour, the skin's edge is
where the colour is half-way between the layer's and the skin's (sub-pixel), just
before the profile settles on the core colour; a layer ends in a step (its edge,
blurred by the optics), while a colour that fades into the skin's over several pixels
is the skin's own shaded rim (dark skin lit from the other side) and not a layer, and
so is a colour only just past the limit of the skin's own (a darker underside): a layer
stands out from the skin at least twice as much as the skin varies.
Points whose profile never settles within the search depth (a tape band that crosses
the whole finger) are dropped, with the outline a quarter of a finger width either
side of them (the band's own edge).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy.ndimage import binary_dilation

from flexcal.vision.order_stats import median
from flexcal.vision.segment import colour_features

STEP_PX = 0.5            # sampling step along the normal
CORE_DEPTH = (0.22, 0.4)  # where the core colour is taken, in finger widths from the outline
SEARCH_DEPTH = 0.3       # how deep an attached layer may be, in finger widths
RUN_PX = 2.0             # the colour must stay core-like this far to count as the skin's edge
LAYER_EDGE_PX = 4.0      # a layer's colour turns into the skin's within this distance
MIN_LAYER_PX = 1.0       # shallower departures are the outline's own blur, not a layer
LAYER_CONTRAST = 2.0     # a layer's colour is this many times further from the core's than the core-like limit
BAND_MARGIN = 0.25       # outline dropped on either side of a band across the finger, in widths
LIGHT_WEIGHT = 0.35      # shading changes brightness across a round finger; colour counts more


def inward_normals(pts, towards):
    """Unit normals of a 1-px resampled outline, turned to point at ``towards`` (per point)."""
    t = np.gradient(pts, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True) + 1e-12
    n = np.column_stack([-t[:, 1], t[:, 0]])
    flip = np.einsum("ij,ij->i", n, towards - pts) < 0
    n[flip] *= -1
    return n


def _profiles(bgr, pts, normals, depth_px):
    """Feature profiles (N, steps, 3) sampled inwards from each point, and the depths."""
    t = np.arange(0.0, depth_px + STEP_PX / 2, STEP_PX, dtype=np.float32)
    xy = pts[:, None, :].astype(np.float32) + normals[:, None, :].astype(np.float32) * t[None, :, None]
    samples = cv2.remap(bgr, xy[..., 0], xy[..., 1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    return colour_features(samples).reshape(len(pts), len(t), 3), t


def _distance(feats, ref):
    d = feats - ref
    return np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2 + (LIGHT_WEIGHT * d[..., 2]) ** 2)


def skin_edge(bgr, pts, normals, width_px):
    """The skin's edge under each outline point of one side of one arm.

    Returns (points, keep): points moved inwards onto the skin's edge where a layer of
    another colour lies on it, and a boolean mask of the points that found skin.
    """
    if len(pts) == 0:
        return pts, np.zeros(0, bool)
    depth = CORE_DEPTH[1] * width_px
    prof, t = _profiles(bgr, pts, normals, depth)
    core = (t >= CORE_DEPTH[0] * width_px) & (t <= CORE_DEPTH[1] * width_px)
    in_core = prof[:, core].reshape(-1, 3)
    ref = np.array([median(in_core[:, c]) for c in range(3)])
    dist = _distance(prof, ref)
    core_dist = dist[:, core].ravel()
    typical = median(core_dist)
    spread = median(np.abs(core_dist - typical))
    thr = max(10.0, typical + 4 * 1.4826 * spread)
    like = dist <= thr
    # like[i, j] and the next RUN_PX of samples all core-like
    run = max(1, int(round(RUN_PX / STEP_PX)))
    c = np.cumsum(np.pad(~like, ((0, 0), (1, 0))), axis=1)
    steady = (c[:, run:] - c[:, :-run]) == 0          # (N, steps - run + 1): samples j..j+run-1 all like
    searchable = t[: steady.shape[1]] <= SEARCH_DEPTH * width_px
    steady &= searchable[None, :]
    found = steady.any(axis=1)
    first = np.where(found, steady.argmax(axis=1), 0)
    # The edge between the layer and the skin is where the colour is half-way between
    # the two (sub-pixel), not where it has become skin (that lies in the skin's
    # shaded rim, deeper where the rim is darker).
    rows = np.arange(len(pts))
    layer = np.where(np.arange(dist.shape[1])[None, :] < first[:, None], dist, 0.0).max(axis=1)
    half = (layer + dist[rows, first]) / 2
    j = np.maximum(first - 1, 0)
    while True:   # step back over samples still below half-way (the blurred transition)
        back = (j > 0) & (dist[rows, j] < half)
        if not back.any():
            break
        j = np.where(back, j - 1, j)
    d0, d1 = dist[rows, j], dist[rows, np.minimum(j + 1, dist.shape[1] - 1)]
    frac = np.clip((d0 - half) / np.maximum(d0 - d1, 1e-6), 0, 1)
    # a layer ends in a step (its edge, blurred by the optics); a colour that fades into
    # the skin's over several pixels is the skin's own shaded rim, not a layer
    idx = np.arange(dist.shape[1])[None, :]
    plateau = (idx < first[:, None]) & (dist >= 0.8 * layer[:, None])
    p_end = np.where(plateau.any(axis=1), dist.shape[1] - 1 - np.argmax(plateau[:, ::-1], axis=1), 0)
    sharp = (first - p_end) * STEP_PX <= LAYER_EDGE_PX
    # a colour only just past the limit of core-like is the skin's shaded rim, its
    # distance hovering about the limit (a layer's edge would move with the noise)
    sharp &= layer >= LAYER_CONTRAST * thr
    shift = np.where((first > 0) & sharp, t[j] + frac * STEP_PX, 0.0)
    shift[shift < MIN_LAYER_PX] = 0.0
    # the outline next to a band that crosses the finger runs along the band's own
    # edge (and the rounded notch the silhouette's closing left there): drop it too
    k = int(round(BAND_MARGIN * width_px))
    if k > 0 and not found.all():
        found = found & ~binary_dilation(~found, np.ones(2 * k + 1, bool))
    return pts + normals * shift[:, None], found


def colour_steps(blurred, pts, normals, depth=3.0):
    """The colour step across an outline at each point (x, y): the feature distance
    between ``depth`` px inwards and outwards along the (unit, inward) normal, on a
    lightly blurred image (nearest pixels)."""
    h, w = blurred.shape[:2]

    def sample(d):
        px = np.clip(np.round(pts[:, 0] + normals[:, 0] * d).astype(int), 0, w - 1)
        py = np.clip(np.round(pts[:, 1] + normals[:, 1] * d).astype(int), 0, h - 1)
        return colour_features(blurred[py, px])

    return _distance(sample(depth), sample(-depth))


def cut_contrast(bgr, whole, piece, min_px=20):
    """How distinct the outline is that ``piece`` (a silhouette within ``whole``) has
    inside ``whole``: the median colour step across it (``colour_steps``); None when
    under ``min_px`` pixels of its outline lie inside ``whole``.

    When fewer colours cut an object off the silhouette, the new outline is where the
    object's colour meets the finger's: a step. Where they cut the finger itself (its
    lit half from its shaded half) the colour changes gradually, and the step is small.
    """
    m = piece.astype(np.uint8)
    outline = (m > 0) & (cv2.erode(m, np.ones((3, 3), np.uint8)) == 0)
    inner = cv2.erode(whole.astype(np.uint8), np.ones((7, 7), np.uint8)) > 0
    ys, xs = np.nonzero(outline & inner)
    if len(ys) < min_px:
        return None
    gy, gx = np.gradient(cv2.GaussianBlur(m.astype(np.float32), (7, 7), 2))
    n = np.column_stack([gx[ys, xs], gy[ys, xs]])
    n /= np.linalg.norm(n, axis=1, keepdims=True) + 1e-9          # into the piece
    steps = colour_steps(cv2.GaussianBlur(bgr, (3, 3), 0), np.column_stack([xs, ys]).astype(float), n)
    return float(np.median(steps))
