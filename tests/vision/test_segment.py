import cv2
import numpy as np
import pytest

from flexcal.vision.segment import _arm_radius, _loose_pieces, _pieces_in, close_ellipse


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
        n, comp, stats, _ = cv2.connectedComponentsWithStats(own, connectivity=8)
        n2, comp2, stats2 = _pieces_in(part, keep, bridge)
        assert n2 == n and np.array_equal(comp2, comp) and np.array_equal(stats2[1:], stats[1:])


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
    assert np.array_equal(loose, (labels == 1) & (np.arange(320) >= 208)[None, :] & (np.arange(240) >= 100)[:, None])
    # touching the silhouette (the band in the tip's colour), it is no loose piece
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
