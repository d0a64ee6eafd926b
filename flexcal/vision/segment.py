"""Find the hand-and-finger silhouette in a photo.

The scene model is deliberately weak, so that it holds for real photos: the finger and
hand form one connected region of similar colour that enters the picture from an edge
(the forearm is cut by the frame) and is elongated (several times longer than wide);
the background (wall, platform) consists of large regions that occupy much of the
picture's border. Colours are clustered with k-means on chromaticity and a damped log
intensity (so that shading across the round finger and shadows on the wall do not
split a surface); clusters that cover a large share of the border, alone or with
clusters of nearly the same colour, are background; what is left is split into
connected parts and the most finger-like part that touches the border wins, chosen
again after bridging bands of a background colour across it (a closing half an arm
wide; when no part was finger-like, the largest one on the border is bridged: a band
near the hand can leave only a squat stub of the forearm there). When that
part crosses the border far more widely than a forearm (a platform joined to the
hand), only the fingertip's own colours are kept. When a measurement is unsure and a
thick piece of the part is in other colours than the forearm's
(``other_colours_thickness``), ``forearm_colours`` gives it the silhouette again in only
the forearm's colours (``forearm_regions``: the colour clusters in which the arm leaves
the picture, and the arm grown from its own colour up to the strongest colour edges,
within the part and over the whole picture; each place where the part leaves the
picture is offered as the forearm's when something joined to it reaches the border too).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import cv2
import numpy as np
from skimage.graph import MCP_Geometric

from flexcal.vision.order_stats import percentile

_CHROMA_SCALE = 300.0
_LIGHT_SCALE = 15.0
_SHADOW_CHROMA = 4.0        # feature units (1.3 % of a channel share)
_SHADOW_RATIO = (0.35, 0.97)  # how much darker a shadow is than the lit surface
# (seen on renders: skin in a white platform's or a wood board's colours, a poster of the
# skin's colours joined to the hand, tape in the wall's colours cutting the finger from
# the hand; a finger out of view is rarer. Colours that cover much of the picture's edge
# are the background's: within an ROI around the hand and finger a platform covers less
# of it, and such renders were measured right)
NO_PART = ("no elongated object in other colours than the background's enters the picture from an edge: the "
           "hand and finger share colours with the wall or a platform, something of their colours is joined to "
           "the hand, a band in the background's colours cuts the finger from the hand, or they are not in view; "
           "give an ROI around the hand and finger, or photograph against a background of another colour with "
           "nothing touching the hand")
_BRIDGED_STUB = 2.0         # a squat piece on the border bridged into a finger-like one at least this many times its size
_SAME_SURFACE = 5.0         # feature distance under which two colour clusters are one surface
_INTERLEAVED = 0.5          # ... or when more than this share of each one's pixels lie next to the other's (a print)
_ARM_COLOUR = 9.0           # squared Mahalanobis distance to the arm's colour: surely the arm's (3 sigma)
_OTHER_COLOUR = (50.0, 25.0)  # ... and surely something else's: features and chromaticity alone (7, 5 sigma)
_SPLIT_KEPT = 0.8           # a silhouette parted from another finger keeps this much of the rest at least
_GROWN_THICKER = 1.5        # the arm grown over the picture is at most this much thicker than the part
_COLOUR_SHARE = 0.03        # a colour cluster on at least this share of a region is one of its colours
_NECK = 0.25                # a loose piece joined to the silhouette only by a strip under this many half widths wide is loose


@dataclass
class Segmentation:
    """The chosen silhouette at working resolution, or the reason there is none."""

    mask: np.ndarray | None
    reason: str = ""
    contrast: float = 0.0       # feature distance between object and background colours
    n_candidates: int = 0
    part: np.ndarray | None = None    # the chosen connected part, before finishing
    labels: np.ndarray | None = None  # every pixel's colour cluster (uint8)
    centres: np.ndarray | None = None  # the clusters' colour features
    background: np.ndarray | None = None  # per cluster, whether it is background
    shadow_is_finger: bool = False    # colours like the wall's in shadow were taken as the finger's
    shadow_left_out: bool = False     # ... or there were such colours, and they were left out
    cut_off: np.ndarray | None = None  # thick pieces of the part the finishing cut off (``_finish``)
    fg: np.ndarray | None = None      # the foreground (before bridging) the part was chosen from
    tip_clusters: np.ndarray | None = None  # per cluster, whether it is one of the fingertip's colours
    tip_half: float = 0.0             # the finger's half width near the tip (``_fingertip``)
    from_stub: bool = False           # nothing was finger-like: the part is the largest on the border, bridged

    @cached_property
    def part_radius(self) -> float:
        """Half width of the widest part of the chosen part (``_arm_radius``), computed once."""
        return _arm_radius(self.part)

    def cut_off_from(self, mask, cut_off) -> np.ndarray | None:
        """Thick pieces apart from the silhouette ``mask`` (this segmentation's, or one
        rebuilt from it): what its finishing cut off (``cut_off``, or None) and the loose
        pieces in the fingertip's colours (``_loose_pieces``), a boolean image or None.

        The fingertip's colours are those near the chosen part's tip and, for a rebuilt
        silhouette, those near its own tip: rebuilt from fewer colours, it can end at a
        band with the rest of the finger beyond it in colours the part's tip lacks. A
        rebuilt silhouette counts all of the part's tip colours, also those it does not
        hold: a piece in them ahead of its tip may be the finger beyond the rebuilt
        "finger" (seed 5000 hard 15: an oval poster joined to the finger's middle, its
        own end on the picture's edge, rebuilt alone in its colours, measured sure and
        straight, 0.4 deg for 13.5, with the finger's piece in the glove's colours just
        ahead of its end), or a poster joined to the fingertip, beside the nail (held-out
        150000 realistic 24: every rebuilt silhouette of the whole finger is refused as
        cut short). Which it is, the colours do not tell; refused either way.
        """
        if self.tip_clusters is None:
            return cut_off
        found = [cut_off, _loose_pieces(self.fg, mask, self.labels, self.tip_clusters, self.tip_half)]
        if mask is not self.mask:
            tip, half = _fingertip(mask)
            own = _tip_clusters(mask, self.labels, tip, half, len(self.centres))
            found.append(_loose_pieces(self.fg, mask, self.labels, own, half))
        found = [f for f in found if f is not None]
        return np.logical_or.reduce(found) if found else None

    @cached_property
    def crossings(self) -> list[np.ndarray]:
        """The part near each place where it crosses the picture's border, the widest
        first (``_crossing_regions``), computed once for all the forearm's alternatives."""
        return list(_crossing_regions(self))


def colour_features(bgr):
    """Per-pixel colour features that shading and shadows barely change.

    Chromaticity (each channel's share of the sum) does not change when a surface is
    lit more or less (the round finger's shading, a shadow on the wall); a damped log
    intensity keeps black, grey and white things apart.
    """
    f = bgr.reshape(-1, 3).astype(np.float32)
    total = f[:, 0] + f[:, 1] + f[:, 2]     # (summing along the short axis is slow)
    total += 30.0
    out = np.empty_like(f)
    for c in (0, 1):                          # g and r shares
        np.divide(f[:, c + 1], total, out=out[:, c])
        out[:, c] *= _CHROMA_SCALE
    # (into a contiguous array first: numpy's log into a strided column is 6x slower)
    out[:, 2] = np.log(total / 3.0)
    out[:, 2] *= _LIGHT_SCALE
    return out


def _chromaticity(centres):
    """The g and r shares of each colour centre without the features' damping, in feature units.

    ``colour_features`` divides by the channel sum plus 30 so that dark pixels do not get
    noisy shares; that also pulls a colour's shares down as it darkens, so a shaded
    surface's features drift away from its lit part's. Undone here from the centre's
    intensity, for comparing a darker colour with a lighter one (is it its shadow?).
    """
    total = np.exp(centres[:, 2] / _LIGHT_SCALE)
    total *= 3.0                                                # channel sum + 30
    undamp = total / np.maximum(total - 30.0, 1.0)
    out = np.empty((len(centres), 2), centres.dtype)
    for c in (0, 1):               # column by column: fast for a whole picture's features
        np.multiply(centres[:, c], undamp, out=out[:, c])
    return out


def _classify(bgr, labels_small, centres):
    """The nearest colour centre of every working-resolution pixel.

    Inside a surface the clustered thumbnail already knows the answer: only pixels near
    a change of cluster in the thumbnail (a 3x3 neighbourhood of its pixels holding more
    than one cluster) are classified one by one.
    """
    h, w = bgr.shape[:2]
    labels = cv2.resize(labels_small, (w, h), interpolation=cv2.INTER_NEAREST)
    k3 = np.ones((3, 3), np.uint8)
    mixed = cv2.dilate(labels_small, k3) != cv2.erode(labels_small, k3)
    mixed = cv2.resize(mixed.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
    at = np.flatnonzero(mixed)      # (taking by index is faster than a boolean mask)
    fe = colour_features(np.take(cv2.GaussianBlur(bgr, (3, 3), 0).reshape(-1, 3), at, axis=0))
    d2 = (centres ** 2).sum(axis=1)[None, :] - 2.0 * (fe @ centres.T)   # |f - c|^2 - |f|^2
    labels.reshape(-1)[at] = d2.argmin(axis=1)
    return labels


def border_pixels(shape):
    """A boolean image that is True on the picture's outermost rows and columns."""
    h, w = shape
    m = np.zeros(shape, bool)
    m[0, :] = m[-1, :] = m[:, 0] = m[:, -1] = True
    return m


def outer_outline(mask) -> np.ndarray | None:
    """The silhouette's outer outline: its longest external contour, every pixel of it,
    as (N, 2) float (x, y); None when the mask is empty."""
    cs, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return max(cs, key=len).reshape(-1, 2).astype(float) if cs else None


def box(mask, margin=1):
    """The bounding box of ``mask``'s non-zero pixels widened by ``margin`` pixels on each
    side (within the picture), as a pair of slices.

    Morphology, distance transforms and connected pieces reach only so far: done on this
    box with a margin as wide as their reach, they give what they give on the whole
    picture, at a fraction of the cost when the mask covers little of it.
    """
    x, y, w, h = cv2.boundingRect(mask.astype(np.uint8))
    return (slice(max(0, y - margin), y + h + margin), slice(max(0, x - margin), x + w + margin))


def close_ellipse(mask, d):
    """``cv2.morphologyEx(mask, cv2.MORPH_CLOSE, <d x d ellipse>)`` of a 0/1 uint8 mask,
    the same pixels, faster for the large kernels a silhouette's closings use.

    OpenCV visits every pixel of a non-rectangular kernel; the ellipse is instead taken
    row by row: a dilation is the largest, over the kernel's rows, of the mask dilated
    by that row's (rectangular) span and shifted by its offset; an erosion is the
    dilation of the complement, complemented (outside the picture counts as background
    for the dilation and as the mask for the erosion, as in OpenCV).
    """
    if d < 15:
        return cv2.morphologyEx(mask, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d)))
    half = (cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d)).sum(axis=1) - 1) // 2   # per kernel row

    def dilate(img):
        h, out, spans = img.shape[0], np.zeros_like(img), {}
        for dy, w in zip(range(-(d // 2), d // 2 + 1), half):
            if abs(dy) >= h:
                continue
            if w not in spans:
                spans[w] = cv2.dilate(img, np.ones((1, 2 * int(w) + 1), np.uint8))
            if dy >= 0:
                cv2.max(out[dy:], spans[w][:h - dy], dst=out[dy:])
            else:
                cv2.max(out[:h + dy], spans[w][-dy:], dst=out[:h + dy])
        return out

    return 1 - dilate(1 - dilate(mask))


def _arm_radius(part) -> float:
    """Half width of the widest part of a silhouette (95th percentile of its distance transform)."""
    part = part.astype(np.uint8)
    part = part[box(part)]    # a pixel of background around it is all the transform needs
    return float(percentile(cv2.distanceTransform(part, cv2.DIST_L2, 3)[part > 0], 95))


def _on_border(img, border):
    """The 8-connected pieces of the 0/1 uint8 image ``img``: (labels image, border pixels
    per label, the labels of the pieces that touch ``border``, in order).

    Only the pieces on the border are looked at one by one (``_pixels``): OpenCV's
    statistics of every piece (``connectedComponentsWithStats``) cost several times the
    labelling, for the specks of a textured wall too.
    """
    n, comp = cv2.connectedComponents(img, connectivity=8)
    touching = np.bincount(comp[border], minlength=n)
    return comp, touching, np.nonzero(touching[1:])[0] + 1


def _pixels(comp, j):
    """Piece ``j`` of the labels image ``comp``: (uint8 mask, its area in pixels)."""
    piece = (comp == j).view(np.uint8)
    return piece, cv2.countNonZero(piece)


def _pick(fg, border):
    """The most finger-like connected part of ``fg`` that touches the border.

    Returns (label, labels image, number of candidates); label None when there is none.
    """
    h, w = fg.shape
    comp, touching, on_border = _on_border(fg, border)
    best, best_score, candidates = None, 0.0, 0
    for i in on_border:
        piece, area = _pixels(comp, i)
        if area < 0.004 * h * w:
            continue
        x, y, bw, bh = cv2.boundingRect(piece)
        # its bounding box with a pixel of margin, so that the distance transform sees
        # the same background around it as in the whole picture
        ya, xa = max(0, y - 1), max(0, x - 1)
        r = _arm_radius(comp[ya:y + bh + 1, xa:x + bw + 1] == i)
        if r < 2:
            continue
        elong = area / (4 * r * r)   # length in widths, for a tube
        if elong < 2.5 or touching[i] > 0.35 * (h + w):
            continue
        candidates += 1
        score = area * min(elong, 12) / 12
        if score > best_score:
            best, best_score = i, score
    return best, comp, candidates


GEODESIC_Q = 4    # geodesic distances are found at this fraction of the resolution


def geodesic_from_border(part, exits=None):
    """The distance of each block of ``GEODESIC_Q`` x ``GEODESIC_Q`` pixels of ``part`` (a
    0/1 image) from where it leaves the picture, along paths inside it, in blocks (at a
    quarter of the resolution: cheap, and a finger is several blocks wide); inf outside
    the part, and everywhere when it does not reach the picture's edge. ``exits``: the
    (x, y) pixels where it leaves the picture, when not every one of its pixels on the
    picture's edge is (a fingertip touching it is not)."""
    q = GEODESIC_Q
    small = cv2.resize(part.astype(np.uint8), (part.shape[1] // q, part.shape[0] // q),
                       interpolation=cv2.INTER_NEAREST) > 0
    if exits is None:
        starts = np.column_stack(np.nonzero(small & border_pixels(small.shape)))
    else:
        starts = np.unique(np.column_stack([np.minimum(exits[:, 1].astype(int) // q, small.shape[0] - 1),
                                            np.minimum(exits[:, 0].astype(int) // q, small.shape[1] - 1)]), axis=0)
        starts = starts[small[starts[:, 0], starts[:, 1]]]
    if len(starts) == 0:
        return np.full(small.shape, np.inf)
    dist, _ = MCP_Geometric(np.where(small, 1.0, np.inf)).find_costs(starts)
    return dist


def _free_end(part):
    """The (row, col) of the part farthest from where it leaves the picture, along the part.

    Distances are geodesic (``geodesic_from_border``): a platform joined to the hand may
    reach farther from the border in a straight line.
    """
    q = GEODESIC_Q
    dist = geodesic_from_border(part)
    if not np.isfinite(dist).any():
        return np.array(np.unravel_index(np.argmax(cv2.distanceTransform(part, cv2.DIST_L2, 3)), part.shape))
    dist[~np.isfinite(dist)] = -1
    r, c = np.unravel_index(np.argmax(dist), dist.shape)
    # a pixel of the part inside that block, at full resolution
    ys, xs = np.nonzero(part[r * q:(r + 1) * q, c * q:(c + 1) * q])
    if len(ys) == 0:
        return np.array([r * q + q // 2, c * q + q // 2])
    return np.array([r * q + ys[len(ys) // 2], c * q + xs[len(xs) // 2]])


def _pieces_in(part, keep, bridge_px):
    """Connected pieces of ``part`` within ``keep`` (boolean per pixel), after closing
    gaps up to about ``bridge_px`` wide (what crosses the arm in other colours: the
    strip, tape), as a 0/1 uint8 image."""
    d = max(3, int(round(bridge_px)) | 1)
    own = (keep & (part > 0)).astype(np.uint8)
    b = box(own, d + 2)
    out = np.zeros(part.shape, np.uint8)
    out[b] = close_ellipse(own[b], d) & part[b]
    return out


def _disk(centre, radius, shape):
    """The pixels within ``radius`` of ``centre`` (row, col) in a picture of ``shape``:
    the window around it (slices) and the disk within that window (boolean)."""
    r = int(np.ceil(radius))
    y0, x0 = max(0, centre[0] - r), max(0, centre[1] - r)
    y1, x1 = min(shape[0], centre[0] + r + 1), min(shape[1], centre[1] + r + 1)
    yy, xx = np.ogrid[y0:y1, x0:x1]
    return (slice(y0, y1), slice(x0, x1)), (yy - centre[0]) ** 2 + (xx - centre[1]) ** 2 <= radius * radius


def _fingertip(part):
    """The part's free end (row, col) (``_free_end``) and the finger's half width there:
    the largest inscribed circle a little way in from the tip (not further: the hand may
    be thicker, or joined to something)."""
    tip = _free_end(part)
    b = box(part)
    dt = np.zeros(part.shape, np.float32)
    dt[b] = cv2.distanceTransform(part[b], cv2.DIST_L2, 3)

    def widest_near_tip(radius):
        """The largest distance to the background within ``radius`` of the tip."""
        win, disk = _disk(tip, radius, dt.shape)
        return float(dt[win][disk].max())

    half = widest_near_tip(10)
    return tip, widest_near_tip(3 * max(half, 2.0))


def _tip_clusters(part, labels, tip, half, k):
    """The fingertip's colours: per each of the ``k`` colour clusters, whether it covers
    at least a tenth of the part within about two finger widths (``half``: the finger's
    half width) of the tip."""
    win, disk = _disk(tip, 4.0 * max(half, 2.0), part.shape)
    region = disk & (part[win] > 0)
    return np.bincount(labels[win][region], minlength=k) >= 0.1 * max(1, region.sum())


def _tip_colours(part, labels, border, tip, half, tip_clusters):
    """The part of ``part`` in the fingertip's own colours (``tip_clusters``: boolean per
    colour cluster), when ``part`` is more than a tube (``tip``, ``half``: ``_fingertip``).

    A platform's face or a patch of wall in a colour of its own can join the hand where
    they touch, giving one part that meets the picture's border over far more than a
    forearm's thickness. The free end is still the fingertip: keep the colours found
    near it (skin, nail, glove), bridge what crosses the arm in other colours (strip,
    tape), and take the piece that holds the tip, if it still leaves the picture.
    """
    # the forearm crosses the border over about one arm's thickness (more when it
    # leaves at a slant); much more is something else joined to the hand
    if int((part & border).sum()) <= 3 * 2 * half:
        return part
    _, comp = cv2.connectedComponents(_pieces_in(part, tip_clusters[labels], half), connectivity=8)
    j = comp[tip[0], tip[1]]
    if j == 0:
        return part
    piece = (comp == j).astype(np.uint8)
    return piece if (piece & border).any() else part


def _loose_pieces(fg, mask, labels, tip_clusters, half):
    """Pieces of the foreground ``fg`` in the fingertip's colours (``tip_clusters``:
    boolean per colour cluster) outside the silhouette ``mask`` and not touching it (but
    by a strip under ``_NECK`` half widths wide), at least half a finger width thick
    (``half``: its half width), within two widths of the silhouette: a boolean image, or
    None when there is none.

    The rest of the finger beyond a band in the background's colours is such a piece
    (apart from the part, or from a silhouette rebuilt from fewer of its colours); so is
    a neighbouring finger (``angle._cut_short`` looks only ahead of the tip).
    """
    b = box(mask, int(4 * max(half, 2.0)) + 2)
    lut = np.zeros(256, np.uint8)
    lut[:len(tip_clusters)] = tip_clusters
    own = cv2.bitwise_and(cv2.LUT(labels[b], lut), fg[b])
    own[mask[b] > 0] = 0
    # a thin strip of those colours does not join a piece to the silhouette (the rim of
    # a finger's side in the tip's colours runs on across a band)
    r = max(1, int(round(_NECK * half)))
    own = cv2.morphologyEx(own, cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1)))
    thick = cv2.distanceTransform(own, cv2.DIST_L2, 3) >= 0.5 * half
    if not thick.any():
        return None
    n, comp = cv2.connectedComponents(own, connectivity=8)
    keep = np.zeros(n, bool)
    keep[comp[thick]] = True
    keep[comp[cv2.dilate(mask[b].astype(np.uint8), np.ones((3, 3), np.uint8)) > 0]] = False
    keep[0] = False
    if not keep.any():
        return None
    loose = np.zeros(mask.shape, bool)
    loose[b] = keep[comp]
    return loose


def _foreground(labels, background):
    """Pixels not in a background cluster, without thin things (cables, wires) and pinholes."""
    h, w = labels.shape
    fg = (~background[labels]).astype(np.uint8)
    # odd: an even kernel's anchor is off its centre, and each of the opening and the
    # closing shifted the mask by a pixel (at 480 px, 6 px wide: the silhouette sat 2 px
    # right of and below the photo's edges, and a turned photo gave another silhouette)
    width_guess = max(3, int(round(min(h, w) * 0.012))) | 1
    kern = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (width_guess, width_guess))
    fg = cv2.morphologyEx(fg, cv2.MORPH_OPEN, kern)      # drops thin things: cables, wires
    return cv2.morphologyEx(fg, cv2.MORPH_CLOSE, kern)


def segment_finger(bgr: np.ndarray, *, k: int = 6, border_share: float = 0.08, seed: int = 0,
                   shadow_as_finger: bool = False) -> Segmentation:
    """Segment the hand and finger in a BGR uint8 image (working resolution).

    Colours like the wall's (or platform's) in shadow are left out, unless nothing
    finger-like is left without them or ``shadow_as_finger`` asks for the silhouette
    with them (then there is none where no colour is like that).
    """
    h, w = bgr.shape[:2]
    # colours are clustered on a thumbnail 160 px on its long side: the same thumbnail,
    # turned, for a photo turned by 90 deg
    f = 160 / max(h, w)
    small = cv2.resize(bgr, (max(8, int(round(w * f))), max(8, int(round(h * f)))), interpolation=cv2.INTER_AREA)
    feats = colour_features(small)
    if small.std() < 2.0:
        return Segmentation(None, "the picture has no contrast (blank, all black or all white)")
    cv2.setRNGSeed(seed)
    crit = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 20, 0.5)
    _, labels_s, centres = cv2.kmeans(feats, k, None, crit, 2, cv2.KMEANS_PP_CENTERS)
    labels_s = labels_s.reshape(small.shape[:2])
    border = border_pixels(labels_s.shape)
    n_border = border.sum()
    share = np.bincount(labels_s[border], minlength=k) / n_border
    # k-means may split one surface into clusters of nearly the same colour (vignetting,
    # texture, a gradient of light), or into the colours of its print (a cutting mat's
    # grid lines and squares): such clusters share their border share
    group = (_same_surface(centres) | _interleaved(labels_s, k)).astype(float) @ share
    background = group > border_share
    # a cluster with a background cluster's chromaticity but somewhat darker is that
    # background in shadow (a black glove on a grey wall is much darker than any shadow)
    chroma = _chromaticity(centres)
    shadow = np.zeros(k, bool)
    for c in np.nonzero(~background)[0]:
        for bg in np.nonzero(background)[0]:
            dchroma = np.linalg.norm(chroma[c] - chroma[bg])
            ratio = np.exp((centres[c, 2] - centres[bg, 2]) / _LIGHT_SCALE)
            if dchroma < _SHADOW_CHROMA and _SHADOW_RATIO[0] < ratio < _SHADOW_RATIO[1]:
                shadow[c] = True
    if shadow_as_finger and not shadow.any():
        return Segmentation(None, "no colour is like the wall's in shadow")
    if (background | shadow).all() or not background.any():
        return Segmentation(None, "could not tell the finger from the background (no distinct foreground colour)")

    labels = _classify(bgr, labels_s.astype(np.uint8), centres)
    border_full = border_pixels((h, w))
    best = None
    if not shadow_as_finger:
        fg = _foreground(labels, background | shadow)
        best, comp, candidates = _pick(fg, border_full)
    shadow_is_finger = False
    if best is None and shadow.any():
        # Skin or a glove of the wall's hue, only darker, looks like the wall in shadow;
        # when nothing finger-like is left without those colours, they may be the
        # finger's (the measurement must then be sure, see angle.py)
        fg = _foreground(labels, background)
        best, comp, candidates = _pick(fg, border_full)
        shadow_is_finger = best is not None
    from_stub = False
    part = (comp == best).view(np.uint8) if best is not None else _largest_on_border(fg, border_full)
    if part is not None:
        # Bridge what crosses the finger in a background colour (tape, a strap, a
        # highlight): close gaps up to half an arm's width, then choose again. The
        # choice may change: tape cut the finger into pieces, each less finger-like than
        # a poster in the picture, and the bridged finger is whole again. When nothing
        # was finger-like, the largest piece on the border is bridged: a band near the
        # hand leaves only the forearm's stub there, too squat with a poster joined to it
        # (held-out 50000 realistic 29). Taken then only when the part chosen holds that
        # piece and the bridge joined it to at least as much again (the finger beyond
        # the band: 2.4-2.9x on held-out photos): a poster on the border joined to a
        # cable is no finger (20000 realistic 56 mirrored, 1.2x: a latex glove in the
        # wall's colours, which finer colours find when no part was found in these), nor
        # is another piece that the closing made elongated (5000 realistic 48 turned).
        r = _arm_radius(part)
        d = max(3, int(round(r)) | 1)
        b = box(fg, d + 2)
        bridged = np.zeros_like(fg)
        bridged[b] = close_ellipse(fg[b], d)
        best2, comp2, candidates2 = _pick(bridged, border_full)
        from_stub = best is None and best2 is not None
        if from_stub and not ((comp2[part > 0] == best2).all()     # (holds the stub)
                              and np.count_nonzero(comp2 == best2) >= _BRIDGED_STUB * part.sum()):
            best2, from_stub = None, False
        if from_stub:
            # in the colours of the last foreground tried: with the colours like the
            # wall's in shadow, when there are any
            shadow_is_finger = bool(shadow.any())
        if best2 is not None:
            best, comp, candidates = best2, comp2, candidates2
    if not shadow_is_finger:
        background = background | shadow
    if best is None:
        return Segmentation(None, NO_PART, n_candidates=candidates)
    part = (comp == best).astype(np.uint8)
    tip, half = _fingertip(part)
    tip_clusters = _tip_clusters(part, labels, tip, half, k)
    filled, cut_off = _finish(_tip_colours(part, labels, border_full, tip, half, tip_clusters), border_full)
    obj = labels[filled.astype(bool)]
    fg_centre = centres[np.bincount(obj, minlength=k).argmax()]
    bg_centre = centres[np.argmax(share)]
    contrast = float(np.linalg.norm(fg_centre - bg_centre))
    return Segmentation(filled, contrast=contrast, n_candidates=candidates, part=part, labels=labels,
                        centres=centres, background=background, shadow_is_finger=shadow_is_finger,
                        shadow_left_out=bool(shadow.any()) and not shadow_is_finger,
                        cut_off=cut_off, fg=fg, tip_clusters=tip_clusters, tip_half=half, from_stub=from_stub)


def _finish(mask, border):
    """The silhouette from a chosen part: thin attachments off, notches closed, holes
    filled. Returns (silhouette, cut_off): ``cut_off`` holds what survived the opening
    but not in the silhouette, thick pieces joined to it by a thin neck only (a poster
    touching the finger; or the finger's own end beyond a band, when the band and the
    finger's lit side are in the background's colours)."""
    # Drop thin attachments (the sensor's lead, wires, a strap's end) by an opening a
    # third as wide as the arm, then keep the piece that still touches the border.
    r = _arm_radius(mask)
    rad = max(1, int(round(0.3 * r)))
    d = max(3, int(round(r)) | 1)
    # all of it within the closing's reach of the mask
    b = box(mask, d + 2)
    shape, mask, border = mask.shape, mask[b], border[b]
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * rad + 1, 2 * rad + 1))
    opened = cv2.morphologyEx(mask, cv2.MORPH_OPEN, disk)
    piece = _largest_on_border(opened, border)
    if piece is not None:
        mask = piece
    # Close notches narrower than half the arm (tape or a strap in a background colour
    # leaves a waist in the silhouette); the only concave corner this rounds is the
    # crease under the knuckle, which the angle measurement leaves out anyway.
    mask = close_ellipse(mask, d)
    # fill holes (nail, creases, tape the colour of the background) inside the silhouette:
    # background regions (4-connected) that do not reach the border, each under a fifth of
    # the silhouette's area. Flood the background from a frame around the picture; what
    # stays unflooded is a hole.
    h, w = mask.shape
    outside = np.zeros((h + 2, w + 2), np.uint8)
    outside[1:-1, 1:-1] = mask
    cv2.floodFill(outside, None, (0, 0), 2, flags=4)
    holes = (outside[1:-1, 1:-1] == 0).astype(np.uint8)
    area = int(mask.sum())
    if holes.sum() >= 0.2 * area:     # some hole may be too big to fill: look at each
        n2, comp2, stats2, _ = cv2.connectedComponentsWithStats(holes, connectivity=4)
        small = stats2[:, cv2.CC_STAT_AREA] < 0.2 * area
        small[0] = False
        holes = small[comp2].astype(np.uint8)
    mask = mask | holes
    filled, cut_off = np.zeros(shape, np.uint8), np.zeros(shape, bool)
    filled[b], cut_off[b] = mask, (opened > 0) & (mask == 0)
    return filled, cut_off


def _crossing_regions(seg: Segmentation):
    """The chosen part within an arm's thickness of each place where it crosses the
    picture's border (runs of the part along the border, gaps of a few pixels joined),
    the widest crossing first."""
    part = seg.part
    border = border_pixels(part.shape)
    contact = (part.astype(bool) & border).astype(np.uint8)
    n, runs, stats, _ = cv2.connectedComponentsWithStats(cv2.dilate(contact, np.ones((5, 5), np.uint8)), connectivity=8)
    reach = 2 * seg.part_radius
    for j in sorted(range(1, n), key=lambda j: -stats[j, cv2.CC_STAT_AREA]):
        crossing = (runs == j) & (contact > 0)
        b = box(crossing, int(reach / 0.9) + 2)    # (the 3x3 transform counts a straight step as 0.955 px)
        region = np.zeros(part.shape, bool)
        region[b] = (cv2.distanceTransform((~crossing[b]).astype(np.uint8), cv2.DIST_L2, 3) <= reach) & (part[b] > 0)
        if region.any():
            yield region


def _same_surface(centres):
    """Per pair of colour clusters, whether they are one surface (nearly the same colour)."""
    return np.linalg.norm(centres[:, None, :] - centres[None, :, :], axis=2) < _SAME_SURFACE


def _interleaved(labels, k):
    """Per pair of colour clusters, whether they are the colours of one printed or woven
    surface: most pixels of each lie next to (3x3) the other's, in the thumbnail. A
    finger's rim and its skin, or a finger and the wall, meet only along a line (a finger
    a few thumbnail pixels thick may count as one surface with its rim: both lie on
    little of the border, so the sum does too)."""
    k3 = np.ones((3, 3), np.uint8)
    counts = np.maximum(np.bincount(labels.ravel(), minlength=k), 1)
    near = np.empty((k, k))
    for i in range(k):
        near[i] = np.bincount(labels[cv2.dilate((labels == i).astype(np.uint8), k3) > 0], minlength=k) / counts
    both = np.minimum(near, near.T) > _INTERLEAVED
    np.fill_diagonal(both, False)
    return both


def _arm_clusters(seg: Segmentation, region) -> np.ndarray:
    """The clusters on at least ``_COLOUR_SHARE`` of ``region``, with the clusters of
    nearly the same colour (light and shade across the arm); background that the
    closings took into the part (between the hand and the cable, say) is not the arm's
    colour."""
    n = np.bincount(seg.labels[region], minlength=len(seg.centres))
    total = n.sum()
    held = n / total >= _COLOUR_SHARE if total else np.zeros(len(n), bool)
    return _same_surface(seg.centres)[held].any(axis=0) & ~seg.background


def forearm_clusters(seg: Segmentation) -> list[np.ndarray]:
    """Per colour cluster, whether the arm is in that colour where it leaves the picture;
    one answer for each place where the chosen part crosses the picture's border, the
    widest first, without repeats (empty without a part).

    The forearm is taken as the chosen part within an arm's thickness of where it crosses
    the border (``_arm_clusters``). When something joined to the finger (a poster, a box)
    also reaches the border, which crossing is the forearm's is not known: each is
    offered, and the caller keeps the one that measures best.
    """
    if seg.part is None:
        return []
    out = []
    for region in seg.crossings:
        kept = _arm_clusters(seg, region)
        if kept.any() and not any(np.array_equal(kept, k) for k in out):
            out.append(kept)
    return out


def forearm_grown(seg: Segmentation, bgr) -> list[tuple[np.ndarray, np.ndarray | None]]:
    """Per place where the chosen part crosses the picture's border (the widest first),
    the arm grown from its own colour up to the strongest colour edges, twice: within the
    part, and over the whole picture; as (boolean per pixel, where it may lie: the part,
    or None for anywhere). Empty without a part.

    Six colour clusters are few for a cluttered wall: a poster behind the finger can share
    a cluster with the skin, the sensor's lead or the finger's shade, and then the
    forearm's clusters bring it back; or the finger's lit skin shares one with the wall,
    and the part ends at the finger's first band. Pixel by pixel instead: the arm's
    colour is the mean and spread of its main cluster where it leaves the picture
    (``bgr`` is the working image). Pixels near that colour (and, unless the finger is in
    the wall's shadow colours, pixels in the arm's clusters whose chromaticity is near
    it: the finger's shaded side) seed the arm; pixels far from it in colour and in
    chromaticity (a darker shade of skin is not far) seed the rest, and so, for the
    growth within the part, does everything outside it. A marker watershed on the colour
    image then divides what is left where the colour changes most: the finger's outline
    against a poster or the wall is a step, its shading a slope.
    """
    if seg.part is None:
        return []
    part = seg.part > 0
    h, w = part.shape
    feats = colour_features(cv2.GaussianBlur(bgr, (3, 3), 0))
    chroma = _chromaticity(feats)
    labels = seg.labels.ravel()
    same = _same_surface(seg.centres)
    k5 = np.ones((5, 5), np.uint8)
    outside = cv2.dilate(seg.part.astype(np.uint8), np.ones((7, 7), np.uint8)) == 0
    out = []
    for region in seg.crossings:
        share = np.bincount(seg.labels[region], minlength=len(seg.centres)).astype(float)
        share[seg.background] = -1
        arm = (same[np.argmax(share)] & ~seg.background)[labels] & region.ravel()
        if arm.sum() < 50:
            continue
        d_colour, d_chroma = _mahalanobis2(feats, feats[arm]), _mahalanobis2(chroma, chroma[arm])
        near_arm = d_colour < _ARM_COLOUR
        if not seg.shadow_is_finger:
            near_arm |= _arm_clusters(seg, region)[labels] & (d_chroma <= _OTHER_COLOUR[1])
        near_arm = near_arm.reshape(h, w).astype(np.uint8)
        far = ((d_colour > _OTHER_COLOUR[0]) & (d_chroma > _OTHER_COLOUR[1])).reshape(h, w).astype(np.uint8)
        for within in (part, None):
            arm_seeds, other_seeds = (near_arm, far) if within is None else (near_arm & within, far & within)
            markers = np.zeros((h, w), np.int32)
            markers[cv2.morphologyEx(other_seeds, cv2.MORPH_OPEN, k5) > 0] = 2
            if within is not None:
                markers[outside] = 2
            markers[cv2.erode(arm_seeds, k5) > 0] = 1
            cv2.watershed(bgr, markers)
            out.append((markers == 1, within))
    return out


def _mahalanobis2(x, ref):
    """Squared Mahalanobis distance of each row of ``x`` to the rows of ``ref`` (their mean
    and covariance, the latter widened by one feature unit squared against noise-free
    renders and flat colours)."""
    mean = ref.mean(axis=0)
    d = np.empty((x.shape[1], len(x)), x.dtype)             # one row per feature: fast sums
    for c in range(x.shape[1]):
        np.subtract(x[:, c], mean[c], out=d[c])
    icov = np.linalg.inv(np.cov(ref.T) + np.eye(x.shape[1])).astype(x.dtype)
    return ((icov @ d) * d).sum(axis=0)


def forearm_regions(seg: Segmentation, bgr) -> list[tuple[np.ndarray, np.ndarray | None]]:
    """The arm's own pixels, in the ways there are to tell them, each with where the
    silhouette rebuilt from them may lie (``forearm_colours``): in the colour clusters in
    which it leaves the picture (``forearm_clusters``), within the part; then grown from
    its colour to the strongest edges (``forearm_grown``)."""
    return forearm_cluster_regions(seg) + forearm_grown(seg, bgr)


def forearm_cluster_regions(seg: Segmentation) -> list[tuple[np.ndarray, np.ndarray]]:
    """The first of ``forearm_regions``, without the growing (cheap): per set of the
    forearm's colour clusters (``forearm_clusters``), its pixels and the part they may
    lie in."""
    part = seg.part > 0 if seg.part is not None else None
    return [(kept[seg.labels], part) for kept in forearm_clusters(seg)]


def other_colours_thickness(seg: Segmentation, keep) -> float:
    """Thickness (px) of the thickest piece of the chosen part outside ``keep`` (boolean
    per pixel, ``forearm_regions``)."""
    other = ((seg.part > 0) & ~keep).astype(np.uint8)
    return 2.0 * float(cv2.distanceTransform(other, cv2.DIST_L2, 3).max()) if other.any() else 0.0


def other_colours_piece_at(seg: Segmentation, keep, point, thick) -> bool:
    """Whether a piece of the chosen part outside ``keep`` (boolean per pixel,
    ``forearm_regions``), at least ``thick`` px thick, reaches within ``thick`` of
    ``point`` (x, y): something of another colour joined there (looked for within four
    times ``thick`` of it)."""
    win, _ = _disk((int(round(point[1])), int(round(point[0]))), 4 * thick, keep.shape)
    other = ((seg.part[win] > 0) & ~keep[win]).astype(np.uint8)
    if not other.any():
        return False
    _, comp = cv2.connectedComponents(other)
    thick_ids = np.unique(comp[cv2.distanceTransform(other, cv2.DIST_L2, 3) >= thick / 2])
    near = _disk((int(round(point[1])) - win[0].start, int(round(point[0])) - win[1].start), thick, other.shape)
    return bool(np.isin(comp[near[0]][near[1]], thick_ids[thick_ids > 0]).any())


def forearm_colours(seg: Segmentation, keep, within=None) -> tuple[np.ndarray, np.ndarray] | None:
    """The silhouette again, of only the forearm's pixels ``keep`` that lie ``within``
    (the part; None: anywhere) (``forearm_regions``), and what its finishing cut off
    (``_finish``).

    When "everything that is not background" joins the hand to something of another
    colour (a poster, a box, the shadow under the finger), the hand and finger are
    still the part in the forearm's own colours (skin or glove): keep those, bridge what
    crosses the arm in other colours (strip, tape) and finish the silhouette as usual.
    None when that leaves nothing that still reaches the border.
    """
    domain = np.ones(keep.shape, np.uint8) if within is None else within.astype(np.uint8)
    border = border_pixels(keep.shape)
    piece = _largest_on_border(_pieces_in(domain, keep, seg.part_radius), border)
    if piece is None or (within is None and _arm_radius(piece) > _GROWN_THICKER * seg.part_radius):
        return None     # grown into the wall (of a colour close to the skin's): no arm
    return _finish(piece, border)


def _largest_on_border(img, border):
    """The largest 8-connected piece of the 0/1 uint8 image ``img`` that touches the
    picture's ``border``, as a uint8 mask; None when none does."""
    comp, _, on_border = _on_border(img, border)
    pieces = [_pixels(comp, j) for j in on_border]
    return max(pieces, key=lambda pa: pa[1])[0] if pieces else None


def split_at_inner_edge(bgr, mask, sides, hand, radius) -> list[tuple[np.ndarray, np.ndarray]]:
    """Two fingers, one behind the other, as one silhouette ``mask``: each finger's
    silhouette with the hand, parted at the strongest colour edges between them.

    ``sides``: the silhouette's two outer sides along the fingers (outline points
    (x, y), one array per side: each side is one finger's outer edge); ``hand``: outline
    points of the hand. Seeds ``radius`` px around those points grow over the colour
    image (a marker watershed): one side's finger grown together with the hand, and the
    other side's finger on its own, meet where the colour changes most between them,
    the front finger's edge across the one behind. Returns, for each side, (the
    silhouette of the hand and that side's finger, the other side's region removed from
    it); not when that finger ends up apart from the hand, nor when the background
    grew into much of the silhouette (``_SPLIT_KEPT``: its colour edges are weak).
    """
    h, w = mask.shape
    inside = mask > 0
    r = max(2, int(round(radius)))

    def seeds(points):
        m = np.zeros((h, w), np.uint8)
        for x, y in np.round(points).astype(int):
            cv2.circle(m, (int(x), int(y)), r, 1, -1)
        return (m > 0) & inside

    side_seeds, hand_seeds = [seeds(p) for p in sides], seeds(hand)
    outside = cv2.dilate(mask.astype(np.uint8), np.ones((3, 3), np.uint8)) == 0
    border = border_pixels(mask.shape)
    out = []
    for keep, drop in ((0, 1), (1, 0)):
        markers = np.zeros((h, w), np.int32)
        markers[outside] = 3
        markers[side_seeds[keep] | hand_seeds] = 1
        markers[side_seeds[drop] & ~hand_seeds] = 2
        cv2.watershed(bgr, markers)
        removed = markers == 2
        # (the watershed's lines between regions stay, unless next to the removed one);
        # then finished as a silhouette is (``_finish``: frayed strands along the parting
        # are opened off, and what the outside grew into, a band in its colours, bridged)
        line = (markers == -1) & (cv2.dilate(removed.astype(np.uint8), np.ones((3, 3), np.uint8)) == 0)
        kept, _ = _finish((inside & ((markers == 1) | line)).astype(np.uint8), border)
        # the finger kept must be joined to the hand (not an island cut off by the growths)
        if side_seeds[keep].any() and kept[side_seeds[keep]].mean() > 0.9 \
                and kept.sum() >= _SPLIT_KEPT * (inside & ~removed).sum():
            out.append((kept & ~removed, removed))
    return out
