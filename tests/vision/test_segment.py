import cv2
import numpy as np
import pytest

from flexcal.vision.segment import (_arm_radius, _largest_on_border, _loose_pieces, _pick, _pieces_in, border_pixels,
                                    close_ellipse, segment_finger, split_at_inner_edge)


def _blobs(rng, shape):
    """A 0/1 mask of a few thick random blobs, some cut by the picture's edge."""
    m = np.zeros(shape, np.uint8)
    h, w = shape
    for _ in range(rng.integers(1, 5)):
        cx, cy = int(rng.integers(-w // 4, w + w // 4)), int(rng.integers(-h // 4, h + h // 4))
        axes = (int(rng.integers(2, max(3, w // 2))), int(rng.integers(2, max(3, h // 2))))
        cv2.ellipse(m, (cx, cy), axes, float(rng.uniform(0, 180)), 0, 360, 1, -1)
    m[rng.random(shape) < 0.02] ^= 1     # pinholes and specks
    return m


@pytest.mark.parametrize("seed", range(4))
def test_close_ellipse_is_opencvs_closing(seed):
    rng = np.random.default_rng(seed)
    for _ in range(25):
        shape = tuple(int(v) for v in rng.integers(5, 200, 2))
        mask = _blobs(rng, shape)
        d = int(rng.integers(1, 45)) * 2 + 1
        want = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d)))
        assert np.array_equal(close_ellipse(mask, d), want), (shape, d)


@pytest.mark.parametrize("seed", range(4))
def test_work_on_the_masks_box_gives_the_whole_pictures_answer(seed):
    # the distance transform and the bridging closing are done on the mask's bounding
    # box (and their reach around it); the answer is the whole picture's
    rng = np.random.default_rng(100 + seed)
    for _ in range(10):
        part = _blobs(rng, (240, 320))
        if not part.any():
            continue
        dt = cv2.distanceTransform(part, cv2.DIST_L2, 3)
        assert _arm_radius(part) == float(np.percentile(dt[part > 0], 95))
        keep = _blobs(rng, part.shape) > 0     # the forearm's colours: some of the part
        bridge = float(rng.uniform(2, 30))
        k = max(3, int(round(bridge)) | 1)
        own = cv2.morphologyEx((keep & (part > 0)).astype(np.uint8), cv2.MORPH_CLOSE,
                               cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))) & part
        assert np.array_equal(_pieces_in(part, keep, bridge), own)


@pytest.mark.parametrize("seed", range(4))
def test_the_largest_piece_on_the_border_is_opencvs(seed):
    # the pieces are labelled without OpenCV's statistics (slow), and only those on the
    # border are measured: the answer is the one the statistics give, specks and all
    rng = np.random.default_rng(200 + seed)
    for _ in range(25):
        shape = tuple(int(v) for v in rng.integers(5, 200, 2))
        img = _blobs(rng, shape)
        border = border_pixels(shape)
        n, comp, stats, _ = cv2.connectedComponentsWithStats(img, connectivity=8)
        on_border = [j for j in range(1, n) if (comp[border] == j).any()]
        got = _largest_on_border(img, border)
        if not on_border:
            assert got is None
            continue
        want = max(on_border, key=lambda j: stats[j, cv2.CC_STAT_AREA])
        assert got is not None and np.array_equal(got > 0, comp == want), shape


def test_a_photo_turned_by_90_deg_is_segmented_like_the_photo():
    # colours are clustered on a thumbnail of the same size whichever way the photo is
    # held (160 px on its long side): turned by 90 deg, the silhouette is the turned
    # silhouette, but for single pixels at its outline (clustered 160 px wide on the
    # short side, a portrait photo lost the hand or the finger in two of these twelve)
    from flexcal.synthetic import render_finger
    from flexcal.vision.segment import segment_finger
    for seed in range(12):
        img, _ = render_finger(40.0, shape=(480, 640), rng=seed, difficulty="realistic")
        a, b = segment_finger(img), segment_finger(np.ascontiguousarray(np.rot90(img)))
        assert (a.mask is None) == (b.mask is None), seed
        if a.mask is not None:
            turned, mask = np.rot90(a.mask) > 0, b.mask > 0
            assert (turned & mask).sum() > 0.8 * (turned | mask).sum(), seed


def test_loose_pieces_are_thick_pieces_in_the_tips_colours_apart_from_the_silhouette():
    # a hand and finger entering from the left, cut by a band at x = 200; beyond it the
    # rest of the finger (tip's colour), a thin wire in the tip's colour, a thick poster in
    # another colour, and a knob of the tip's colour joined to the part
    labels = np.zeros((240, 320), np.uint8)              # cluster 0: the wall
    labels[100:140, 0:200] = 1                            # hand and finger, up to the band
    labels[100:140, 208:260] = 1                          # the finger beyond the band
    labels[30:33, 40:200] = 1                             # a wire, 3 px
    labels[170:220, 100:160] = 2                          # a poster
    labels[140:160, 60:90] = 1                            # a knob on the hand
    fg = (labels > 0).astype(np.uint8)
    part = np.zeros_like(fg)
    part[100:160][labels[100:160] == 1] = 1
    part[:, 200:] = 0
    tip_clusters = np.array([False, True, False])
    loose = _loose_pieces(fg, part, labels, tip_clusters, half=20.0)
    assert loose is not None, "the finger beyond the band"
    beyond = (labels == 1) & (np.arange(320) >= 208)[None, :] & (np.arange(240) >= 100)[:, None]
    assert not (loose & ~beyond).any() and loose[beyond].mean() > 0.95    # (its corners rounded)
    # joined to the silhouette only by a strip of the tip's colour 3 px wide (the rim of
    # the finger's side running on across the band), it is still loose
    rim = labels.copy()
    rim[100:103, 200:208] = 1
    loose = _loose_pieces((rim > 0).astype(np.uint8), part, rim, tip_clusters, half=20.0)
    assert loose is not None and not (loose & ~beyond).any() and loose[beyond].mean() > 0.95
    # joined across the band's whole width (the band in the tip's colour), it is no loose piece
    labels[100:140, 200:208] = 1
    assert _loose_pieces((labels > 0).astype(np.uint8), part, labels, tip_clusters, half=20.0) is None


def test_the_colours_of_a_printed_grid_are_one_surface_a_fingers_are_not():
    from flexcal.vision.segment import _interleaved
    labels = np.zeros((120, 160), np.uint8)          # 0: a mat's squares
    labels[::6, :] = 1                               # 1: its grid lines
    labels[:, ::6] = 1
    labels[40:70, :] = 2                             # 2: a hand lying across it
    labels[40:42, :] = 3                             # 3: the hand's lit rim
    both = _interleaved(labels, 4)
    assert both[0, 1] and both[1, 0]
    assert not both[2].any() and not both[:, 2].any() and not both[3].any()


def _tube(shape, p0, p1, half_width):
    m = np.zeros(shape, np.uint8)
    cv2.line(m, tuple(int(v) for v in p0), tuple(int(v) for v in p1), 1, 2 * half_width)
    cv2.circle(m, tuple(int(v) for v in p1), half_width, 1, -1)
    return m > 0


@pytest.mark.parametrize("seed", [0, 1])
def test_two_overlapping_fingers_are_parted_at_the_front_fingers_edge(seed):
    # a hand from the left edge, and at its end two fingers from one knuckle: the one
    # behind (darker) bent further. The front finger's edge across the one behind is
    # the only colour step between them
    rng = np.random.default_rng(seed)
    shape, knuckle = (300, 420), np.array([200.0, 100.0])
    hand = _tube(shape, (0, 100), knuckle, 20)
    front_tip = knuckle + 170 * np.array([np.cos(np.radians(20)), np.sin(np.radians(20))])
    back_tip = knuckle + 160 * np.array([np.cos(np.radians(40)), np.sin(np.radians(40))])
    front, back = _tube(shape, knuckle, front_tip, 15), _tube(shape, knuckle, back_tip, 15)
    img = np.full(shape + (3,), (200, 210, 205), np.float32)
    img[back] = (80, 110, 160)
    img[hand | front] = (100, 140, 200)
    img = np.clip(img + rng.normal(0, 3, img.shape), 0, 255).astype(np.uint8)
    mask = (hand | front | back).astype(np.uint8)
    # seeds: each finger's outer edge (the front one's upper side, the back one's lower
    # side, half-way along), and the hand where it leaves the picture
    along = np.linspace(0.4, 0.8, 20)[:, None]
    up = np.array([np.sin(np.radians(20)), -np.cos(np.radians(20))])
    down = np.array([-np.sin(np.radians(40)), np.cos(np.radians(40))])
    front_side = knuckle + along * (front_tip - knuckle) + 14 * up
    back_side = knuckle + along * (back_tip - knuckle) + 14 * down
    hand_pts = np.array([[2.0, y] for y in range(85, 116)])
    splits = split_at_inner_edge(img, mask, [front_side, back_side], hand_pts, 4)
    # (kept the other way, the finger behind may end up apart from the hand: not offered)
    tip = np.round(front_tip - 10 * (front_tip - knuckle) / 170).astype(int)
    kept, removed = next((k, r) for k, r in splits if k[tip[1], tip[0]])   # the front finger's side kept
    behind_only = back & ~front & ~hand
    assert np.mean(kept[front | hand]) > 0.97
    assert np.mean(kept[behind_only]) < 0.05 and np.mean(removed[behind_only]) > 0.95


@pytest.mark.parametrize("seed", [0, 1])
def test_a_finger_cut_into_pieces_by_bands_is_chosen_over_a_poster_once_bridged(seed):
    # bands in the wall's colour cut the finger into pieces: the hand's piece on the
    # border is too squat to be finger-like, and a slender poster on the picture's edge
    # is the most finger-like part; bridged, the finger is whole again and chosen
    rng = np.random.default_rng(seed)
    shape = (480, 640)
    hand, finger = _tube(shape, (-40, 300), (120, 300), 40), _tube(shape, (120, 300), (480, 330), 22)
    poster = np.zeros(shape, np.uint8)
    cv2.ellipse(poster, (600, 0), (28, 250), 0, 0, 360, 1, -1)
    img = np.full(shape + (3,), 150, np.float32)
    img[poster > 0] = (140, 110, 220)
    img[hand | finger] = (120, 150, 205)
    for x in (180, 300, 410):
        band = np.zeros(shape, bool)
        band[:, x - 9:x + 9] = True
        img[band & (hand | finger)] = 150
    img = cv2.GaussianBlur(img + rng.normal(0, 4, img.shape).astype(np.float32), (0, 0), 1.2)
    seg = segment_finger(np.clip(img, 0, 255).astype(np.uint8))
    best, comp, _ = _pick(seg.fg, border_pixels(shape))
    unbridged = comp == best
    assert (unbridged & (poster > 0)).sum() > 0.8 * unbridged.sum()
    mask = seg.mask > 0
    assert (mask & finger).sum() > 0.95 * finger.sum() and not (mask & (poster > 0)).any()
