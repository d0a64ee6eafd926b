import re
from pathlib import Path

import cv2
import numpy as np
import pytest

from flexcal.synthetic import draw_finger, render_finger
from flexcal.vision import as_bgr8, draw_overlay, contact_sheet, measure_angle
from flexcal.vision.markers import find_markers
from flexcal.vision.measurement import AngleMeasurement, failed

SHAPE = (480, 640)
# The renders named below for the case they show (a seed, often the benchmark's photo)
# were found on hands without a palm, as the presets drew them until 2026-11-27; they
# keep that hand (``palm_mm=NO_PALM``), and with it the case. Seeded sets take the
# presets' hands, with a palm.
NO_PALM = 0.0


@pytest.fixture
def found_without_a_palm(monkeypatch):
    """For a case (a render named for it, ``NO_PALM``) whose silhouette's hand is under
    1.3x as thick as its finger, the least a hand with a palm is
    (``MIN_HAND_TO_FINGER``; two fingers together look so): the case's own path is
    checked with the least it was found under (1.1, for hands without a palm), not
    refused before it."""
    from flexcal.vision import angle
    monkeypatch.setattr(angle, "MIN_HAND_TO_FINGER", 1.1)


def _clean_set(n, seed, bends=(0, 90), shape=SHAPE, palm_mm=None):
    """``n`` seeded clean renders (angle, image, truth) bent within ``bends``; with
    ``palm_mm`` (lo, hi), each hand's palm is drawn from that range instead of the
    preset's."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a = float(rng.uniform(*bends))
        r = int(rng.integers(2**31))
        palm = {} if palm_mm is None else {"palm_mm": float(rng.uniform(*palm_mm))}
        img, truth = render_finger(a, shape=shape, rng=r, difficulty="clean", **palm)
        yield a, img, truth


@pytest.fixture(scope="module")
def clean_results():
    return [(a, measure_angle(img)) for a, img, _ in _clean_set(24, seed=101)]


def test_accuracy_on_clean_renders(clean_results):
    answered = [(a, m) for a, m in clean_results if m.status != "failed"]
    assert len(answered) >= 0.8 * len(clean_results)
    err = np.array([abs(m.angle_deg - a) for a, m in answered])
    # stated tolerances for clean photos (the benchmark tracks the tighter targets)
    assert np.percentile(err, 90) < 2.0
    # the finger's edges are taken along the phalanx's straight shaft, not where its base
    # flares into the knuckle (with edges from 0.6 widths of the knuckle: median 0.43)
    assert np.median(err) < 0.35
    for _, m in answered:
        assert 0 <= m.confidence <= 1 and m.method == "contour"


def test_uncertainty_is_honest(clean_results):
    answered = [(a, m) for a, m in clean_results if m.status != "failed"]
    inside = np.mean([abs(m.angle_deg - a) <= 2 * m.angle_unc_deg for a, m in answered])
    assert inside >= 0.8
    assert all(m.angle_unc_deg > 0 for _, m in answered)


@pytest.fixture(scope="module")
def reference_photo():
    # (a hand without a palm: with the preset's, 9 mm, the photo at half size, its finger
    # 18 px wide, measures 53.0 deg, 1.0 from the full size's, within its 1.3 deg
    # uncertainty but beyond this test's 0.8; turned, mirrored and doubled it holds)
    img, truth = render_finger(52.0, shape=SHAPE, rng=7, difficulty="clean", roll_deg=0.0, palm_mm=NO_PALM)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    return img, truth, m


@pytest.mark.parametrize("transform", ["rot90", "rot180", "rot270", "mirror", "flipud", "half", "double"])
def test_invariance_to_rotation_mirroring_and_scale(reference_photo, transform):
    img, truth, m0 = reference_photo
    t = {
        "rot90": lambda x: np.rot90(x, 1), "rot180": lambda x: np.rot90(x, 2), "rot270": lambda x: np.rot90(x, 3),
        "mirror": np.fliplr, "flipud": np.flipud,
        "half": lambda x: cv2.resize(x, None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA),
        "double": lambda x: cv2.resize(x, None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC),
    }[transform]
    m = measure_angle(np.ascontiguousarray(t(img)))
    assert m.status != "failed", m.reason
    assert m.angle_deg == pytest.approx(m0.angle_deg, abs=0.8)
    assert m.angle_deg == pytest.approx(truth.angle_deg, abs=1.5)


def test_vertex_lies_near_the_knuckle(reference_photo):
    _, truth, m = reference_photo
    assert np.hypot(*(np.array(m.vertex) - truth.vertex_xy)) < 15 * truth.px_per_mm


def test_grey_uint16_and_float_inputs_give_the_same_answer(reference_photo):
    img, _, m0 = reference_photo
    m16 = measure_angle(img.astype(np.uint16) * 257)
    assert m16.angle_deg == pytest.approx(m0.angle_deg, abs=0.05)
    mf = measure_angle(img.astype(np.float32) / 255)
    assert mf.angle_deg == pytest.approx(m0.angle_deg, abs=0.2)


def test_a_grey_photo_is_refused_saying_so():
    # a realistic render whose colour photo is measured right; in grey its finger is no
    # distinct colour. (A grey render was once measured 0.7 deg for 85, sure: the
    # refusal says why, where the silhouette alone would not.)
    img, truth = render_finger(85.38, shape=SHAPE, rng=249, difficulty="realistic", palm_mm=NO_PALM)
    assert abs(measure_angle(img).angle_deg - truth.angle_deg) < 1.5
    grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)
    ok, jpeg = cv2.imencode(".jpg", cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR), [cv2.IMWRITE_JPEG_QUALITY, 85])
    for picture in (grey, grey.astype(np.uint16) * 257, cv2.imdecode(jpeg, cv2.IMREAD_COLOR)):
        for method in ("auto", "contour", "markers"):
            m = measure_angle(picture, method=method)
            assert m.status == "failed" and "grey" in m.reason, (method, m.angle_deg, m.reason)


def test_a_colour_photo_of_grey_things_is_not_taken_for_a_grey_photo():
    # a black glove on a grey wall and platform: the light's colour and the camera's
    # white balance tint a tenth of the pixels by more than the grey photo's 0-1 levels
    img, truth = render_finger(40.0, shape=SHAPE, rng=3, difficulty="clean", glove="black",
                               background_bgr=(150, 150, 150), platform="grey")
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)
    assert "grey" in measure_angle(cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)).reason


def test_roi_gives_the_same_angle_in_full_image_coordinates(reference_photo):
    img, truth, m0 = reference_photo
    x0, y0 = 40, 30
    m = measure_angle(img, roi=(x0, y0, img.shape[1] - x0, img.shape[0] - y0))
    assert m.angle_deg == pytest.approx(m0.angle_deg, abs=1.0)
    assert np.hypot(*(np.array(m.vertex) - np.array(m0.vertex))) < 10
    with pytest.raises(ValueError, match="roi"):
        measure_angle(img, roi=(0, 0, 5000, 10))


def test_marker_method():
    img, truth = render_finger(63.0, shape=SHAPE, rng=3, markers=True)
    m = measure_angle(img, method="markers")
    assert m.status == "ok" and m.method == "markers"
    assert m.angle_deg == pytest.approx(63.0, abs=0.5)
    assert np.hypot(*(np.array(m.vertex) - truth.markers_xy[1])) < 1.0
    assert measure_angle(img).method == "markers"           # auto picks the dots
    plain, _ = render_finger(63.0, shape=SHAPE, rng=3)
    assert measure_angle(plain, method="markers").status == "failed"


@pytest.mark.parametrize("angle,seed,difficulty", [(57.326551858930884, 0, "clean"), (84.87504950151309, 4, "clean"),
                                                   (72.45026313708422, 5, "clean"), (56.25859199442003, 7, "clean"),
                                                   (25.571235631539295, 171688720, "realistic")])
def test_marker_dots_on_a_saturated_finger_are_found(angle, seed, difficulty):
    # tanned skin is saturated itself (HSV saturation 125-135 of 255 near the dots in
    # the clean renders), and so is a blue nitrile glove (170, the realistic one, whose
    # blue dot is on its own blue): dots found by a fixed saturation threshold joined
    # the finger and none was found; a dot is found as standing out in colour from
    # what is round it
    img, truth = render_finger(angle, rng=seed, difficulty=difficulty, markers=True)
    hsv = cv2.cvtColor(img, cv2.COLOR_BGR2HSV)
    x, y = truth.markers_xy[1].astype(int)
    assert np.median(hsv[y - 40:y + 41, x - 40:x + 41, 1]) >= 120     # the case in point
    dots = np.array([d[:2] for d in find_markers(img)])
    assert len(dots) == 3
    assert all(np.min(np.hypot(*(dots - t).T)) < 1.0 for t in truth.markers_xy)
    m = measure_angle(img)
    assert m.method == "markers" and m.angle_deg == pytest.approx(angle, abs=0.5)


@pytest.mark.parametrize("image,why", [
    (np.zeros((1, 1, 3), np.uint8), "too small"),
    (np.zeros((480, 640, 3), np.uint8), "blank"),
    (np.full((480, 640, 3), 255, np.uint8), "blank"),
    (np.full((480, 640, 3), (30, 40, 200), np.uint8), "blank"),    # one flat colour that is not grey
    (np.random.default_rng(0).integers(0, 255, (480, 640, 3), dtype=np.uint8), ""),
    (np.zeros((10, 10, 7), np.uint8), "shape"),
])
def test_bad_pictures_fail_as_values(image, why):
    m = measure_angle(image)
    assert m.status == "failed" and not m and np.isnan(m.angle_deg)
    assert why in m.reason and m.reason


def test_bad_method_raises():
    with pytest.raises(ValueError, match="method"):
        measure_angle(np.zeros((64, 64), np.uint8), method="hough")


def test_overlay_and_contact_sheet(reference_photo):
    img, _, m = reference_photo
    ov = draw_overlay(img, m)
    assert ov.shape == img.shape and not np.array_equal(ov, img)
    # the overlay marks the vertex in magenta
    x, y = (int(round(v)) for v in m.vertex)
    assert tuple(ov[y, x]) == (255, 0, 255)
    sheet = contact_sheet([ov, as_bgr8(img[..., 0])], ["a", "b"], ["ok", "failed"], cols=2)
    assert sheet.shape[1] > 2 * 300 and sheet.dtype == np.uint8


@pytest.fixture(scope="module")
def refused_photo():
    """A clean render with an orange bar joined to the finger and reaching the picture's
    bottom edge (something joined to the finger: refused), the bar's and the hand and
    finger's pixels."""
    img, truth = render_finger(40, shape=(960, 1280), rng=0, difficulty="clean")
    bar = np.zeros(truth.mask.shape, bool)
    bar[530:, 410:490] = True
    img[bar] = (0, 140, 255)
    return img, bar, truth.mask


def _inside(outline, shape):
    inside = np.zeros(shape, np.uint8)
    cv2.fillPoly(inside, [np.round(outline).astype(np.int32)], 1)
    return inside.astype(bool)


def _outlines_what_was_taken(outline, bar, hand, region=None):
    """The outline holds the bar and the hand and finger (all but the sensor's strip
    along the top, which the silhouette leaves out), and little else."""
    got = _inside(outline, bar.shape)
    region = np.ones(bar.shape, bool) if region is None else region
    near = cv2.dilate((bar | hand).astype(np.uint8), np.ones((11, 11), np.uint8)) > 0
    assert (got & bar & region).sum() >= 0.95 * (bar & region).sum()
    assert (got & hand & region).sum() >= 0.9 * (hand & region).sum()
    assert (got & ~near).sum() <= 0.02 * got.sum()


def test_a_refusal_outlines_what_was_taken_for_the_hand_and_finger(refused_photo, tmp_path):
    from flexcal.measure import measure_photo
    img, bar, hand = refused_photo
    m = measure_angle(img)
    assert m.status == "failed" and "leaves the picture in 2 places" in m.reason, m.reason
    _outlines_what_was_taken(m.outline, bar, hand)
    # the overlay draws it, in the refusal's red, all the way round
    ov = draw_overlay(img, m)
    x, y = (np.clip(np.round(m.outline[:, k]).astype(int), 0, img.shape[1 - k] - 1) for k in (0, 1))
    assert np.mean(np.abs(ov[y, x].astype(int) - img[y, x].astype(int)).max(axis=1) > 40) > 0.95
    # read from a JPEG at half size, as `flexcal measure` reads it: in the photo's pixels
    path = tmp_path / "refused.jpg"
    cv2.imwrite(str(path), img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    m, _, reduction = measure_photo(path)
    assert reduction == 2 and m.status == "failed"
    _outlines_what_was_taken(m.outline, bar, hand)
    # within an ROI: in the photo's pixels too
    region = np.zeros(bar.shape, bool)
    region[100:, :] = True
    m = measure_angle(img, roi=(0, 100, 1280, 860))
    assert m.status == "failed"
    _outlines_what_was_taken(m.outline, bar, hand, region)


def test_an_answer_has_no_outline(reference_photo):
    # (the arms say what was measured)
    assert reference_photo[2].status == "ok" and reference_photo[2].outline is None


def test_round_coloured_things_off_the_finger_are_not_markers():
    img, truth = render_finger(35.0, shape=(480, 640), rng=21, difficulty="clean")
    # three saturated discs on the background, like a poster or pen caps
    ys, xs = np.nonzero(~truth.mask)
    rng = np.random.default_rng(2)
    placed = []
    while len(placed) < 3:
        i = rng.integers(len(xs))
        x, y = int(xs[i]), int(ys[i])
        if 20 < x < 620 and 20 < y < 460 and not truth.mask[max(0, y - 20):y + 20, max(0, x - 20):x + 20].any() \
                and all(np.hypot(x - a, y - b) > 80 for a, b in placed):
            placed.append((x, y))
    for (x, y), colour in zip(placed, [(0, 0, 255), (255, 0, 0), (0, 200, 0)]):
        cv2.circle(img, (x, y), 8, colour, -1, cv2.LINE_AA)
    assert measure_angle(img, method="markers").method == "markers"     # asked for: the dots are used
    m = measure_angle(img)                                               # auto: they are not on the finger
    assert m.method == "contour"
    assert abs(m.angle_deg - truth.angle_deg) < 2.0


def test_specks_on_the_finger_are_not_marker_dots(tmp_path):
    # turned upside down, this photo (no markers) has three small saturated specks on the
    # silhouette (bits of the lead, of tape edges) that auto took for marker dots: a
    # sure 43 deg for a 23 deg bend. Stickers are a third of the finger's thickness
    row = _as_saved_photo(tmp_path, 23.31534195231147, 651621405, "hard", transform=lambda im: im[::-1, ::-1])
    assert row["method"] == "contour"


def test_an_object_joined_to_the_hand_is_refused_not_measured():
    img, truth = render_finger(60.0, shape=(480, 640), rng=7, difficulty="clean", sensor=False, palm_mm=NO_PALM)
    assert measure_angle(img).status == "ok"
    # a rod in the hand's own colour standing on the back of the hand, into free space
    core = cv2.erode(truth.mask.astype(np.uint8), np.ones((15, 15), np.uint8)) > 0
    colour = np.median(img[core], axis=0).astype(int).tolist()
    x, y = (int(v) for v in truth.proximal_xy[4])             # on the hand's axis, behind the knuckle
    cv2.line(img, (x, y), (x, y - 150), colour, 18, cv2.LINE_AA)
    from flexcal.vision.angle import _measure_silhouette, _segment
    work, f, seg = _segment(img)
    m = _measure_silhouette(work, f, seg.mask, seg.contrast, cut_off=seg.cut_off)
    assert m.status == "failed" and "forks" in m.reason
    # the fixes a user has: the other fingers out of the way, the object moved, an ROI
    assert all(fix in m.reason for fix in ("curl the other fingers", "move the object", "ROI"))
    # the arm grown from its colour over the picture leaves the rod's blurred sides out,
    # and the rod (under half a finger wide) then drops as a thin attachment: measuring
    # that silhouette is fine, being misled by the rod is not
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - truth.angle_deg) < 1.5


def test_skin_edge_is_found_under_a_strip_and_tape_is_dropped():
    from flexcal.vision.edges import skin_edge
    img = np.full((120, 200, 3), (200, 205, 210), np.uint8)
    img[40:80, :] = (120, 150, 200)                  # a horizontal "finger", skin coloured
    img[40:45, :] = (45, 45, 45)                     # a dark strip on its top edge, 5 px
    img[36:84, 120:140] = (220, 225, 228)            # a tape band across it, wider than it
    xs = np.arange(10, 190, 1.0)
    top = np.column_stack([xs, np.full_like(xs, 39.5)])
    normals = np.tile([0.0, 1.0], (len(xs), 1))
    pts, keep = skin_edge(img, top, normals, width_px=40)
    on_tape = (xs >= 118) & (xs <= 141)
    # the band and the outline just beside it (its own edge) are dropped, the rest kept
    assert not keep[(xs > 112) & (xs < 146)].any()
    assert keep[(xs < 105) | (xs > 154)].all()
    # under the strip the edge is the strip/skin boundary (y = 44.5), not the outline
    assert np.allclose(pts[~on_tape, 1], 44.5, atol=0.6)
    assert keep.sum() > 0.7 * len(xs)


def test_a_silhouette_with_no_facing_midline_where_the_knuckle_is_sought_is_refused():
    # in nine colours this cluttered photo's silhouette had no facing pairs over the
    # stretch searched for the knuckle, and the search raised an IndexError. (The arm
    # grown from its own colour then measures it: 1.9 deg for 2.7.)
    from flexcal.vision.angle import _measure_segmentation, _measure_silhouette, _segment, _two_line_scores
    from flexcal.vision.segment import segment_finger
    cands = np.arange(100.0, 140.0)
    assert np.isinf(_two_line_scores(np.zeros((0, 2)), np.zeros(0), 0.0, 300.0, cands - 10, cands + 15)).all()
    angle = 2.6709327157127505
    img, _ = render_finger(angle, shape=(960, 1280), rng=924267260, difficulty="realistic")
    work, f, _ = _segment(img)
    nine = segment_finger(work, k=9)
    m = _measure_silhouette(work, f, nine.mask, nine.contrast, cut_off=nine.cut_off)
    assert m.status == "failed" and m.reason
    m = _measure_segmentation(work, f, nine)
    assert m.status == "failed" or abs(m.angle_deg - angle) < 1.5


def test_two_line_scores_match_one_fit_per_candidate_and_find_the_bend():
    from flexcal.vision.angle import _fit_line, _two_line_scores
    rng = np.random.default_rng(5)
    # a midline that runs straight for 120 px, then turns by 40 deg at s = 120
    s = np.sort(rng.uniform(0, 300, 900))
    d1, d2 = np.array([1.0, 0.0]), np.array([np.cos(np.radians(40)), np.sin(np.radians(40))])
    mid = np.where((s < 120)[:, None], s[:, None] * d1, 120 * d1 + (s - 120)[:, None] * d2)
    mid = mid + rng.normal(0, 0.3, mid.shape)
    cands = np.arange(60.0, 240.0, 4.0)
    got = _two_line_scores(mid, s, 20.0, 290.0, cands - 10, cands + 15)
    for b, score in zip(cands, got):
        pf = mid[(s >= 20) & (s <= b - 10)]
        ph = mid[(s >= b + 15) & (s <= 290)]
        r2 = np.sort(np.concatenate([_fit_line(pf)[2], _fit_line(ph)[2]]) ** 2)
        assert score == pytest.approx(r2[: int(len(r2) * 0.8)].mean(), rel=1e-6)
    assert abs(cands[np.argmin(got)] - 120) <= 12


@pytest.mark.parametrize("angle", [45.0, 60.0])
def test_an_object_of_another_colour_behind_the_finger_is_left_out(angle):
    from flexcal.vision.angle import _measure_silhouette, _segment
    img, truth = render_finger(angle, shape=(480, 640), rng=5, difficulty="clean", palm_mm=NO_PALM)
    # a magenta box behind the fingertip, joined to the finger's silhouette
    d = truth.distal_xy
    p = d[-1] + (d[-1] - d[0]) / np.linalg.norm(d[-1] - d[0]) * 35
    box = np.zeros(img.shape[:2], np.uint8)
    cv2.rectangle(box, (int(p[0]) - 10, int(p[1]) - 10), (int(p[0]) + 110, int(p[1]) + 90), 1, -1)
    img[(box > 0) & ~truth.mask] = (200, 40, 200)
    work, f, seg = _segment(img)
    first = _measure_silhouette(work, f, seg.mask, seg.contrast)
    assert first.status == "failed" and first.details.get("foreign")   # the box made the finger look too wide
    m = measure_angle(img)                     # measured again in the forearm's own colours
    assert m.status == "ok"
    assert abs(m.angle_deg - angle) < 1.5


def test_consensus_line_follows_the_straight_stretch_only():
    from flexcal.vision.angle import _consensus_line, _robust_line
    rng = np.random.default_rng(4)
    x = np.arange(0.0, 120.0)
    y = 0.1 * x + rng.normal(0, 0.15, x.size)          # a straight edge, 5.71 deg
    y[:12] += 0.004 * (12 - x[:12]) ** 2               # the end of the knuckle's flare
    y[105:] -= 0.01 * (x[105:] - 105) ** 2             # it turns at the next joint
    y[45:75] += 3.0                                    # a tape band stands off over the middle quarter
    pts = np.column_stack([x, y])
    c, d, r, w = _consensus_line(pts, tol=0.6)
    err = abs(np.degrees(np.arctan2(d[1], d[0])) % 180 - np.degrees(np.arctan(0.1)))
    assert err < 0.15
    # the band is left out, the straight edge on both sides of it kept
    assert not w[45:75].any() and w[12:45].all() and w[75:105].all()
    # the robust fit it starts from is pulled further by the ends
    d_all = _robust_line(pts)[1]
    assert abs(np.degrees(np.arctan2(d_all[1], d_all[0])) % 180 - np.degrees(np.arctan(0.1))) > err


@pytest.mark.parametrize("step", [+0.15, -0.15])
def test_a_band_is_found_where_the_silhouette_widens_or_narrows_on_both_sides(step):
    # tape of the glove's colour stands off the finger (the silhouette widens); tape of
    # another colour is left out of it, and the silhouette's closing leaves a notch
    # across the finger (it narrows); either way on both sides alike, the midline
    # straight through. Where something is joined to one side or bites into it, the
    # midline moves by a quarter width or more: no band.
    from flexcal.vision.angle import _bands
    wf = 40.0
    s = np.arange(0.0, 8 * wf)
    rng = np.random.default_rng(7)
    width = wf * (1.0 + 0.01 * rng.standard_normal(s.size))
    on = (s >= 3 * wf) & (s < 3.5 * wf)
    width[on] += step * wf
    mid = np.column_stack([s, np.zeros_like(s)])
    bands = _bands(mid, s, width, wf)
    assert len(bands) == 1
    lo, hi = bands[0]
    assert lo < 3 * wf < 3.5 * wf < hi and hi - lo < 1.2 * wf
    one_side = mid.copy()
    one_side[on, 1] += 0.25 * wf
    assert _bands(one_side, s, width, wf) == []


def test_a_bent_second_joint_is_not_taken_for_the_knuckle():
    # a nearly straight knuckle (4 deg) and a second joint bent by 20 deg: the second
    # joint lies under 4.8 finger widths from the tip, too close to be the knuckle,
    # so the photo is refused or measured at the knuckle, never answered with its bend
    for seed in range(6):
        img, _ = render_finger(4.0, shape=SHAPE, rng=seed, difficulty="clean", pip_deg=20.0, tape=True)
        m = measure_angle(img)
        assert m.status == "failed" or abs(m.angle_deg - 4.0) < 5.0, (seed, m.angle_deg)


def test_a_cutting_mat_platform_is_background():
    # k-means splits the mat's face into two clusters of colour, one of them on less than
    # 12 % of the picture's border: it must still count as background, not join the hand
    img, truth = render_finger(42.0, shape=(960, 1280), rng=3, difficulty="clean", platform="mat",
                               background_bgr=(43, 149, 101), skin_tone=0.63)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - 42.0) < 1.5


@pytest.mark.parametrize("angle, rng", [(1.8170988147678613, 2094958335), (44.02510738483107, 1765408964),
                                        (57.54954062326768, 334161958)])
def test_a_cutting_mat_whose_grid_lines_take_a_cluster_is_background(tmp_path, angle, rng):
    # the mat's grid lines take a colour cluster of their own, with most of the mat's
    # share of the border; its green squares, on 6 % of the border, joined the hand
    # ("no elongated object", or the hand 2.3x the finger). The two colours lie next to
    # each other everywhere on the mat: one printed surface
    _assert_measured(tmp_path, angle, rng, "clean", tol=1.0)


def test_a_hand_wider_than_a_hand_is_refused():
    img, truth = render_finger(45.0, shape=SHAPE, rng=7, difficulty="clean", sensor=False)
    assert measure_angle(img).status == "ok"
    # a slab in the hand's own colour along its back, from behind the knuckle out of the
    # picture: the "hand" is now 2.5 times as thick as the finger
    core = cv2.erode(truth.mask.astype(np.uint8), np.ones((15, 15), np.uint8)) > 0
    colour = np.median(img[core], axis=0).astype(int).tolist()
    p = truth.proximal_xy
    d = (p[-1] - p[1]) / np.linalg.norm(p[-1] - p[1])
    n = np.array([-d[1], d[0]])
    n = n if n[1] < 0 else -n                                   # the back of the hand is up
    half = 11.0 * truth.px_per_mm
    a, b = p[2], p[2] + d * 2000
    slab = np.array([a + n * 0.5 * half, b + n * 0.5 * half, b + n * 2.6 * half, a + n * 2.6 * half])
    cv2.fillPoly(img, [slab.astype(np.int32)], colour)
    m = measure_angle(img)
    assert m.status == "failed" and "wider than a hand" in m.reason


@pytest.mark.parametrize("seed", [4, 5, 6])
def test_a_tape_band_in_the_background_colour_is_not_a_joint(seed):
    # the light tape band on a light wall leaves a notch in the silhouette inside the
    # finger's window; the midline bends there, the skin's edges do not
    angle = 30.0 + 5 * seed
    img, _ = render_finger(angle, shape=SHAPE, rng=seed, difficulty="clean", tape=True, background_bgr=(200, 208, 212),
                           palm_mm=NO_PALM)
    m = measure_angle(img)
    assert m.status != "failed", m.reason
    assert abs(m.angle_deg - angle) < 2.5


@pytest.mark.parametrize("angle, seed", [(30.0, 2), (60.0, 1)])
def test_a_dark_object_joined_to_the_finger_is_left_out(angle, seed):
    from flexcal.vision.angle import _measure_silhouette, _segment
    img, truth = render_finger(angle, shape=SHAPE, rng=seed, difficulty="clean", palm_mm=NO_PALM)
    # a dark blue disc behind the finger's back, touching it
    d = truth.distal_xy
    u = (d[-1] - d[0]) / np.linalg.norm(d[-1] - d[0])
    n = np.array([u[1], -u[0]])
    n = -n if np.dot(n, truth.proximal_xy[-1] - truth.proximal_xy[0]) > 0 else n
    c = d[4] + n * 40
    disc = np.zeros(img.shape[:2], np.uint8)
    cv2.ellipse(disc, (int(c[0]), int(c[1])), (45, 28), float(np.degrees(np.arctan2(u[1], u[0]))), 0, 360, 1, -1)
    img[(disc > 0) & ~truth.mask] = (90, 30, 30)
    work, f, seg = _segment(img)
    assert not _measure_silhouette(work, f, seg.mask, seg.contrast)   # the joined silhouette is refused
    m = measure_angle(img)                   # measured again without the disc's colour
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.5


@pytest.mark.parametrize("seed", [0, 2, 3])
def test_the_shaded_side_of_pale_skin_on_a_lilac_wall_is_not_the_walls_shadow(seed):
    # the shaded underside of very light skin has the lilac wall's damped colour features
    # (the features' shares fall as a colour darkens); its true chromaticity is the skin's
    img, _ = render_finger(14.0, shape=SHAPE, rng=seed, difficulty="clean", skin_tone=0.0,
                           background_bgr=(183, 155, 188), platform="grey", light_deg=-110.0, shadow=0.3)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - 14.0) < 1.5


def test_a_fingertip_cut_by_the_frame_is_refused_with_that_reason():
    img, truth = render_finger(80.0, shape=SHAPE, rng=3, difficulty="clean")
    ys = np.nonzero(truth.mask.any(axis=1))[0]
    cut = img[: ys.max() - 15]                  # the frame's lower edge crosses the fingertip
    m = measure_angle(cut)
    assert m.status == "failed" and "leaves the picture in 2 places" in m.reason


def test_a_fingertip_just_touching_the_frame_is_measured():
    # the frame's lower edge grazes the fingertip: the silhouette touches it over less
    # than the finger is thick, the tip is there (cut a little), and the hand still
    # leaves the picture in one place only
    img, truth = render_finger(80.0, shape=SHAPE, rng=3, difficulty="clean")
    ys = np.nonzero(truth.mask.any(axis=1))[0]
    m = measure_angle(img[: ys.max() - 3])
    assert m.status == "ok" and abs(m.angle_deg - 80.0) < 1.5, (m.angle_deg, m.reason)


@pytest.mark.parametrize("turn", [None, np.rot90, np.fliplr])
def test_a_fingertip_whose_shadow_reaches_the_frame_is_measured(turn):
    # held-out 130000 realistic render 4: the fingertip and its shadow touch the
    # picture's edge over 24 px at half size, the finger some 30 px thick there. It was
    # refused, the silhouette leaving the picture "in 2 places", in every orientation
    a = 73.54709684766213
    img, _ = _benchmark_photo(a, 1533442073, "realistic", transform=turn)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - a) < 1.5, (m.angle_deg, m.reason)


def test_a_slender_finger_is_measured_at_its_knuckle():
    # phalanges 35 % longer for the same thickness (a slender adult finger seen from the
    # side): the knuckle lies about 8.5 finger widths from the tip, beyond the usual
    # range; and on a light wall the nail of dark skin is left out of the silhouette,
    # whose narrow tip must not be taken for the finger's width. Either would put both
    # arms on the straight finger and answer ~0 deg with full confidence.
    errors, answered = [], 0
    for i in range(12):
        angle = 5.0 + (i * 37) % 80
        img, truth = render_finger(angle, shape=SHAPE, rng=100 + i, difficulty="clean", finger_length=1.35,
                                   scale=0.85)
        m = measure_angle(img)
        if m.status != "failed":
            answered += 1
            errors.append((i, round(m.angle_deg - truth.angle_deg, 1)))
    assert all(abs(e) < 4.0 for _, e in errors), errors
    assert answered >= 9, errors


def test_no_knuckle_beyond_the_range_when_the_range_gives_straight_arms():
    # held-out 150000 hard render 10: a finger bent 10.6 deg, tape either side of the
    # knuckle. Within the usual range the arms are both straight and give 8.7 deg,
    # unsure; the search beyond it put the "knuckle" on the hand, 8.6 widths from the
    # tip, and measured the hand against itself: 3.9 deg, sure
    a = 10.605031728086288
    img, _ = _benchmark_photo(a, 826656271, "hard")
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - a) < max(3.0, 2 * m.angle_unc_deg), (m.angle_deg, m.reason)


@pytest.mark.parametrize("turn", [lambda im: np.rot90(im, -1), np.fliplr], ids=["turned by 90 deg", "mirrored"])
def test_no_knuckle_beyond_the_range_that_bends_less_than_the_hand_arm_within_it(turn):
    # the benchmark's hard render 95 of seed 2026 with a palm (``--palm-mm 5,10``): a
    # finger bent 73.5 deg, the middle finger behind it. Within the usual range the
    # hand's arm is bent by 14-16 deg inside (the knuckle lies in it); the search beyond
    # the range put both arms on the hand: 0.2 and 1.1 deg, sure
    a = 73.47337778329951
    img, _ = _benchmark_photo(a, 2101350159, "hard", transform=turn, palm_mm=8.918375584481733)
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - a) < max(3.0, 2 * m.angle_unc_deg), (m.angle_deg, m.reason)


def test_a_finger_bent_far_from_a_hand_with_a_palm_is_measured_at_its_knuckle():
    # the benchmark's realistic render 90 of seed 2026 with a palm (``--palm-mm 5,10``):
    # bent 84.5 deg, the palm's pad fills the bend's inner corner, whose sides do not
    # face across for more than a finger width; without that stretch of midline the
    # knuckle was placed a width into the hand, the bend in the finger's window: refused
    # ("an arm is not straight (bent by 56 deg inside it)"). The knuckle sought over the
    # bend's corner measured it; since session 63 the forearm's colours, sure too, come first
    a = 84.53975250219757
    img, _ = _benchmark_photo(a, 956506073, "realistic", palm_mm=6.869522332149889)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - a) < 2.5, (m.angle_deg, m.reason)


def test_a_reading_past_the_palms_pad_that_moves_the_answer_beyond_its_doubt_is_not_taken():
    # the benchmark's hard render 80 of seed 5000 with a palm, turned by 180 deg: bent 3.8
    # deg; the silhouette measures 4.3, past the palm's pad 0.1, sure, 3.7 deg off
    _assert_refused_or_within(3.839448151788969, 107056222, "hard", 2.0, transform=lambda im: np.rot90(im, 2),
                              palm_mm=7.676104570225446)


def test_the_knuckle_sought_over_the_bends_corner_answers_when_nothing_else_is_sure():
    # the benchmark's realistic render 73 of seed 5000 with a palm: bent 79.1 deg, every
    # other silhouette of it refused; over the bend's corner, 0.1-0.5 deg off in every turn
    a = 79.14037589131902
    img, _ = _benchmark_photo(a, 259918226, "realistic", palm_mm=9.084729673978885)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - a) < 2.0, (m.angle_deg, m.reason)
    assert m.details["via"] == "the bend's corner"


@pytest.mark.parametrize("angle, rng, difficulty, palm_mm, turn", [
    (85.1812987988469, 775287543, "realistic", 7.443838984179198, lambda im: np.rot90(im, -1)),
    (74.2726825082987, 231452516, "hard", 8.469535372224913, np.fliplr),
    (76.20050446169347, 1908606121, "realistic", 8.781185671375425, lambda im: np.rot90(im, 2))],
    ids=["2026 realistic 38 turned by 90 deg", "2026 hard 48 mirrored", "5000 realistic 76 turned by 180 deg"])
def test_a_sure_reading_over_the_bends_corner_gives_way_to_one_in_the_forearms_colours(angle, rng, difficulty,
                                                                                          palm_mm, turn):
    # a tape band in the finger's window bends it, and the knuckle sought over the bend's
    # corner leans: 3.8, 4.2 and 4.3 deg too large, sure; the silhouettes rebuilt in the
    # forearm's colours, sure too, 0.3-0.9 deg off
    img, _ = _benchmark_photo(angle, rng, difficulty, transform=turn, palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 2.0, (m.angle_deg, m.details.get("via"))


def test_a_finger_edge_hidden_near_the_knuckle_is_named_in_the_refusal():
    # the benchmark's hard render 29 of seed 2026 turned by 90 deg (73.6 deg, the preset's
    # 5.1 mm palm): one side of the finger's window has under 8 skin-edge points, and too
    # few where that side's edge is followed beyond it (a tape band, the bend's corner).
    # Refused, and no longer "the arms are too short to fit lines to", which said neither
    # which arm nor what hid it. (Until the edge beyond the window was taken, this was
    # realistic render 38 of seed 5000, now measured: 87.2 deg for 85.4)
    img, _ = _benchmark_photo(73.56462588957683, 1406023319, "hard", transform=lambda im: np.rot90(im, -1),
                              palm_mm=5.108824283080357)
    m = measure_angle(img)
    assert m.status == "failed"
    assert m.reason.startswith("the finger's edge is hidden on one side where its direction is measured (0.7-2.0 "
                               "finger widths from the knuckle"), m.reason
    assert "tape band" in m.reason and len(m.reason.splitlines()) == 1


@pytest.mark.parametrize("angle, rng, difficulty, palm_mm, turn", [
    (51.361735825018265, 1975632250, "realistic", 5.843292634503015, None),
    (2.2677587159435255, 1563888019, "hard", 9.668545302958954, np.fliplr)],
    ids=["5000 realistic 23", "20000 hard 71 mirrored"])
def test_an_arm_whose_edges_are_far_from_parallel_is_not_measured_sure_on_its_midline(angle, rng, difficulty,
                                                                                       palm_mm, turn):
    # Edges over 12 deg apart are no arm's two sides; the arm's direction is then the
    # midline's, which was the answer's check. Taken as sure, it followed a wall of the
    # skin's colour beyond the hand cut off at a tape band (7.0 deg for 51.4) and a cable
    # along the hand of a finger with another one at its tip (12.6 for 2.3). Refused, or
    # answered right.
    img, _ = _benchmark_photo(angle, rng, difficulty, transform=turn, palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - angle) < 5.0, (m.angle_deg, m.status)


@pytest.mark.parametrize("angle, rng, palm_mm", [
    (51.4059126963792, 248541903, 9.776092493626257),
    (20.83634404022309, 1203047367, 6.04387211701413)],
    ids=["render 75", "render 0, black glove"])
def test_a_hand_whose_edges_run_straight_is_not_bent_by_its_midline(angle, rng, palm_mm):
    # seed 5000's realistic renders, both with the sensor's two tape bands: the hand's band,
    # left out of the silhouette on one side, leaves a shallow notch that the edges drop
    # but the midline follows, by a pixel or two, enough over the hand's window to read as
    # a bend of 9-11 deg inside it. Both edges run straight: refused before, 51.5 and 21.6 deg
    img, _ = _benchmark_photo(angle, rng, "realistic", palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.5, (m.angle_deg, m.reason)


def test_a_strip_of_a_black_glove_whose_hand_turns_three_widths_on_is_not_measured():
    # seed 10000's hard render 32 turned by 180 deg (a black glove against a dark wall and
    # box): rebuilt in the forearm's colours, the silhouette keeps only a strip of the
    # glove half the finger thick; with widths that small both arms lie on the
    # finger, 0.8 deg for 44, sure. Beyond the arm taken for the hand the strip turns by
    # 49-51 deg and widens, from 3 widths on: the knuckle, there
    angle = 43.969012898690615
    img, _ = _benchmark_photo(angle, 1860274004, "hard", transform=lambda im: np.rot90(im, 2),
                              palm_mm=7.209942674161646)
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - angle) < 5.0, (m.angle_deg, m.status)


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (21.526917891244015, 1671580633, 5.681554241753448, None),
    (64.59735981303457, 489294111, 6.880474488639534, lambda im: np.rot90(im, -1))],
    ids=["20000 render 51", "10000 render 37 turned by 90 deg"])
def test_two_fingertips_in_a_rebuilt_silhouette_are_not_measured_as_one(angle, rng, palm_mm, turn):
    # held-out hard renders, another finger behind the finger: rebuilt in the forearm's
    # colours, the silhouette takes in both fingertips, narrower near the knuckle (0.89-0.93
    # of their width) and the hand only 1.32-1.35 times as thick as them; the knuckle,
    # sought so many of those widths from the tip, lands too near it, and the answers
    # were 27.5 deg for 21.5 and 69.9 for 64.6, sure
    img, _ = _benchmark_photo(angle, rng, "hard", transform=turn, palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status != "ok" or abs(m.angle_deg - angle) < 3.0, (m.angle_deg, m.status)


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (4.205303705265086, 848564613, 7.764288412796665, None),
    (14.370566943973474, 1071663681, 9.074456018316909, None),
    (41.61512322830025, 1208676011, 9.444154012156748, lambda im: np.rot90(im, 1))],
    ids=["2026 render 10", "5000 render 82", "10000 render 94 turned by 270 deg"])
def test_two_fingertips_side_by_side_are_not_measured_as_one_finger(angle, rng, palm_mm, turn):
    # hard renders, the middle finger behind the index and bent 9-13 deg further: the
    # silhouette, as segmented, holds both fingertips, so the finger is narrower in its
    # window than near its "tip" (0.85-0.88x) and the hand only 1.33-1.35 times as thick
    # as that tip; the knuckle, sought so many of those widths from the tip, is misplaced
    # and the answers were 6.5 deg for 4.2 (sure), 18.7 for 14.4 and 46.8 for 41.6 (sure)
    _assert_refused_or_within(angle, rng, "hard", 2.0, transform=turn, palm_mm=palm_mm)


def test_a_finger_whose_edges_run_straight_is_not_bent_by_its_midline():
    # seed 2026's realistic render 97 turned by 90 deg (both tape bands, the second joint
    # bent by 15 deg): rebuilt in the forearm's colours, the finger's band standing off
    # one side near the bend's corner bends the midline in the finger's window by 12 deg
    # while both edges run straight; refused there, the first silhouette's unsure 82.3 deg
    # was the answer
    angle = 86.46875495634715
    img, _ = _benchmark_photo(angle, 721837863, "realistic", transform=lambda im: np.rot90(im, -1),
                              palm_mm=8.58039538131122)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.5, (m.angle_deg, m.status, m.reason)


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (65.40992190936814, 60629099, 8.883009898794185, lambda im: np.rot90(im, -1)),
    (84.53975250219757, 956506073, 6.104877312956069, lambda im: np.rot90(im, 2))],
    ids=["render 91 turned by 90 deg", "render 90 turned by 180 deg"])
def test_a_finger_edge_hidden_in_its_window_is_taken_beyond_it(angle, rng, palm_mm, turn):
    # the benchmark's realistic renders of seed 2026 (large bends, the presets' palms): a
    # tape band and the bend's corner leave one side of the finger's window with 0-4
    # skin-edge points, but that side's edge runs on beyond the window, straight, parallel
    # to the other side. Both were refused ("the finger's edge is hidden on one side");
    # fitted to the edge beyond the window, 66.0 and 84.8 deg
    img, _ = _benchmark_photo(angle, rng, "realistic", transform=turn, palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.5, (m.angle_deg, m.reason)
    assert m.details["finger_edge_beyond_window"], m.details


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (18.804219030159537, 1980092670, 7.029974525530163, lambda im: np.rot90(im, -1)),
    (16.64273678080549, 785905980, 9.721643335565485, None)],
    ids=["2026 render 19 turned by 90 deg", "5000 render 89"])
def test_the_midline_and_the_edges_disagreeing_widen_the_uncertainty(angle, rng, palm_mm, turn):
    # the benchmark's realistic renders (the presets' palms): the midline's bend and the
    # edges' differ by 1.7 and 2.1 deg (a palm's pad in the hand's window), and the
    # edges' answer is 1.5 and 2.5 deg off, outside twice the lines' own uncertainty (0.7
    # and 1.1 deg); half the difference added (1.1 and 1.5 deg), it lies within. (Until
    # session 63 the first was 2026 render 38 turned by 90 deg, answered over the bend's
    # corner 3.8 deg off; now in the forearm's colours, 0.8 off, the two agreeing)
    img, _ = _benchmark_photo(angle, rng, "realistic", transform=turn, palm_mm=palm_mm)
    m = measure_angle(img)
    assert m.status != "failed", m.reason
    assert abs(m.angle_deg - angle) <= 2 * m.angle_unc_deg, (m.angle_deg, m.angle_unc_deg)
    disagree = m.details["midline_disagree_deg"]
    assert disagree > 1.5 and m.angle_unc_deg >= 0.5 * disagree, (disagree, m.angle_unc_deg)


@pytest.mark.parametrize("turn", [None, lambda im: np.rot90(im, -1)], ids=["as rendered", "turned by 90 deg"])
def test_the_finger_width_is_not_taken_from_a_piece_beside_the_finger(turn):
    # Where the silhouette is 1.3x wider 2.5-4 widths from the tip than near it, the tip
    # is taken to be cut (a nail left out) and the width is taken further on; but not
    # from a tube onto no tube. The benchmark's realistic render 80 of seed 5000 with a
    # palm (``--palm-mm 5,10``): a card behind the finger, joined over most of its
    # length, was taken for the finger's shaft (no pair faces across there): the width
    # doubled, both arms on the hand, 2.2 deg for 45.3, sure, in every orientation.
    # (Render 39 without a palm, the fingertip joined to its shadow, a blob that faces
    # across little itself, was the case for taking the width past it; measured so, its
    # finger is 1.2x as thick as the hand, now refused as two fingers; with the preset's
    # palm it is measured right without that rule)
    a = 45.333898540100385
    img, _ = _benchmark_photo(a, 1196819312, "realistic", transform=turn, palm_mm=8.958031954682623)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - a) < 1.5, (m.angle_deg, m.reason)


def test_no_knuckle_sought_further_within_the_range_at_a_bent_second_joint():
    # held-out 20000 realistic render 18 turned by 270 deg: a finger bent 3.6 deg at the
    # knuckle, its second joint bent, which lies in the finger's window of the usual
    # search (refused: "an arm is not straight"). The search over a longer stretch of
    # midline puts the knuckle at that joint, within the usual range, sure: 12.4 deg,
    # when such answers were taken (tried in session 46 for a palm's knuckle left a
    # width into the hand)
    a = 3.6084583430784467
    img, _ = _benchmark_photo(a, 961475815, "realistic", transform=lambda im: np.rot90(im, 1))
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - a) < max(3.0, 2 * m.angle_unc_deg), (m.angle_deg, m.reason)


def test_small_bends_of_a_finger_on_a_hand_with_a_palm_are_measured_without_a_lean():
    # a palm 7-10 mm thicker than the finger: its pad, rounding off beyond the knuckle,
    # tilted the hand's arm and pushed the knuckle into the hand (this set: median error
    # 0.42 deg, every answer but two too large, by 0.42 on average); measured past the pad
    # as accurately as a hand without one (test_accuracy_on_clean_renders)
    errors, ways = [], []
    for a, img, _ in _clean_set(12, seed=44, bends=(0, 45), palm_mm=(7, 10)):
        m = measure_angle(img)
        assert m.status != "failed", m.reason
        errors.append(m.angle_deg - a)
        ways.append(m.details.get("via"))
    assert np.median(np.abs(errors)) < 0.35 and abs(np.mean(errors)) < 0.3, np.round(errors, 2)
    assert ways.count("past the palm's pad") >= 6, ways


def test_large_bends_of_a_finger_on_a_hand_with_a_palm_have_the_hands_arm_past_its_pad():
    # bent 45-90 deg, a palm 7-10 mm thick: the hand's window, from 0.9 widths beyond the
    # knuckle, took in the end of the palm's pad (this set: mean error 0.40 deg, up to
    # 0.93); from 1.4 widths it does not
    errors = []
    for a, img, _ in _clean_set(16, seed=45, bends=(45, 90), shape=(960, 1280), palm_mm=(7, 10)):
        m = measure_angle(img)
        assert m.status != "failed" and m.details.get("via") == "past the palm's pad", (m.reason, m.details.get("via"))
        errors.append(abs(m.angle_deg - a))
    assert np.mean(errors) < 0.35 and max(errors) < 0.75, np.round(errors, 2)


# the first ten of the benchmark's realistic renders (seed 5000, as rendered, with the
# presets' palms) answered on a silhouette rebuilt in the forearm's colours: (bend, render
# seed, palm mm)
FOREARM_COLOURS_WITH_A_PALM = [
    (52.485213174292234, 1551817798, 8.596447165693048), (53.35487982533511, 1651152057, 7.894507228954895),
    (41.84074509875122, 653852867, 8.799655794266211), (81.33803021974063, 1208114259, 5.019600222303743),
    (41.902384976799695, 1691753842, 5.2328836355890544), (85.22585465937689, 1985575073, 6.602478991828211),
    (74.82261389734481, 2107644345, 9.777348185355232), (1.3184767442857104, 529320371, 9.614556813423263),
    (23.971094327377063, 1139765134, 6.151804189246947), (13.663358148089936, 1750065357, 7.024091949846362)]


def test_a_silhouette_rebuilt_in_the_forearms_colours_is_measured_past_the_palms_pad():
    # the rebuilt silhouette holds the same palm as the first: measured once, its hand's
    # arm took in the pad (these ten: mean error 0.70 deg, 3.16 at most, the five too
    # large by 1.24 on average); past the pad, as the first silhouette is. (Render 23.97
    # deg has been answered on its first silhouette since its hand's midline, wobbling
    # at a band left out on one side, no longer bends the hand's straight edges.)
    errors, rebuilt = [], 0
    for a, rng, palm in FOREARM_COLOURS_WITH_A_PALM:
        img, _ = _benchmark_photo(a, rng, "realistic", palm_mm=palm)
        m = measure_angle(img)
        via = m.details.get("via")
        assert m.status == "ok" and via in ("forearm's colours; past the palm's pad", "past the palm's pad"), (
            a, m.reason, via)
        rebuilt += via.startswith("forearm's colours")
        errors.append(m.angle_deg - a)
    assert rebuilt >= 9, rebuilt
    assert np.mean(np.abs(errors)) < 0.5 and max(np.abs(errors)) < 2.0, np.round(errors, 2)


def test_wall_taken_in_between_the_cable_and_the_hand_is_not_a_forearm_colour():
    # the sensor's cable runs off the picture beside the hand; the closings fill the
    # strip of wall between them, so the wall lies inside the part where the arm leaves
    # the picture. It must not count as the arm's colour, or rebuilding the silhouette
    # in the forearm's colours keeps the cable and the wall, and the photo is refused.
    img, truth = render_finger(85.0, shape=SHAPE, rng=4, difficulty="clean", cable=True, background="fabric",
                               background_bgr=(213, 42, 49), pip_deg=16.8, roll_deg=11.3, light_deg=-21.0,
                               shadow=0.42, skin_tone=0.59, offset_px=(-13.0, 5.0))
    from flexcal.vision.angle import _segment
    from flexcal.vision.segment import forearm_clusters
    work, _, seg = _segment(img)
    assert not any((kept & seg.background).any() for kept in forearm_clusters(seg))
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - truth.angle_deg) < 1.5


def test_the_shaded_rim_of_dark_skin_is_not_a_layer_on_it():
    # dark skin lit from above: the finger's underside darkens gradually towards its
    # outline. Taken for a layer (like the sensor strip) at some points and not at
    # others, it made the finger's edge zigzag and tilted its line by 7 deg.
    img, truth = render_finger(45.0, shape=SHAPE, rng=5, difficulty="clean")
    assert truth.params.skin_tone > 0.7 and truth.params.light_deg < -60
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - truth.angle_deg) < 1.5


def test_a_knuckle_found_at_the_nearest_place_it_can_be_is_a_bent_second_joint():
    # a nearly straight knuckle (3 deg) and the second joint bent by 17 deg, in a latex
    # glove with tape: where the best place for the knuckle is the near end of its
    # range, the bend found there is the second joint's; never answered with it
    for seed in range(16):
        img, _ = render_finger(3.0, shape=SHAPE, rng=seed, difficulty="clean", pip_deg=17.0, tape=True,
                               glove="latex", blur_sigma=0.7)
        m = measure_angle(img)
        assert m.status == "failed" or abs(m.angle_deg - 3.0) < 5.0, (seed, m.angle_deg)


@pytest.mark.parametrize("angle, seed", [(60.0, 3), (45.0, 5)])
def test_a_board_joined_to_the_fingertip_that_reaches_the_frame_is_left_out(angle, seed):
    # a teal board behind the fingertip runs down to the picture's bottom edge: the
    # silhouette leaves the picture twice, and which crossing is the forearm's is not
    # known; the silhouette is rebuilt from each crossing's colours and the best kept
    img, truth = render_finger(angle, shape=SHAPE, rng=seed, difficulty="clean")
    d = truth.distal_xy
    p = d[-1] + (d[-1] - d[0]) / np.linalg.norm(d[-1] - d[0]) * 30
    box = np.zeros(img.shape[:2], np.uint8)
    cv2.rectangle(box, (int(p[0]) - 60, int(p[1]) - 20), (int(p[0]) + 60, SHAPE[0] - 1), 1, -1)
    img[(box > 0) & ~truth.mask] = (150, 140, 30)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - angle) < 1.5


def test_captions_wrap_at_words_and_say_when_cut():
    from flexcal.vision.overlay import _fit_lines
    for reason in ("step_04_030deg.jpg: the silhouette leaves the picture in 2 places: the fingertip, or "
                   "something joined to the hand or finger, reaches the picture's edge; keep the fingertip in "
                   "the frame",
                   "step_06_050deg.jpg: the edges of an arm are not parallel (9 deg apart); much of an arm's "
                   "outline is not straight; the midline and the edges disagree by 2.3 deg"):
        lines = _fit_lines(reason, 320, 0.45, max_lines=2)
        assert len(lines) == 2 and lines[-1].endswith("...")
        words = set(reason.split())
        for line in lines:
            assert cv2.getTextSize(line, cv2.FONT_HERSHEY_SIMPLEX, 0.45, 1)[0][0] <= 320
            assert all(w in words for w in line.removesuffix("...").split())    # no word cut in two
    assert _fit_lines("a.jpg: 12.3 deg", 320, 0.45, max_lines=2) == ["a.jpg: 12.3 deg"]


def test_a_hand_twice_as_thick_as_the_fingertip_is_measured():
    # real hands seen from the side are about twice as thick across the palm as the
    # finger near its tip (the renders' default hand is 1.5x): such photos must not be
    # taken for "something joined to the hand", nor lose the knuckle
    errors = []
    for seed in range(12):
        angle = 10.0 + (seed * 23) % 75
        img, truth = render_finger(angle, shape=SHAPE, rng=seed, difficulty="clean", palm_mm=8.0)
        m = measure_angle(img)
        assert m.status != "failed", (seed, m.reason)
        assert m.details["hand_to_finger_width"] > 1.8
        errors.append(abs(m.angle_deg - truth.angle_deg))
    assert max(errors) < 2.5 and np.median(errors) < 1.0, errors


def test_finishing_fills_small_holes_and_keeps_big_ones():
    from flexcal.vision.segment import _finish, border_pixels
    mask = np.zeros((200, 300), np.uint8)
    mask[20:180, 0:280] = 1                 # an arm leaving the picture on the left
    mask[80:90, 220:230] = 0                # a nail-sized hole: filled
    mask[60:140, 30:140] = 0                # a hole of a quarter of the silhouette: kept
    out, cut_off = _finish(mask, border_pixels(mask.shape))
    assert not cut_off.any()
    assert out[85, 225] == 1
    assert out[100, 85] == 0 and out[100, 40] == 0
    assert out[30, 200] == 1 and out[100, 290] == 0 and out[10, 100] == 0


@pytest.mark.parametrize("seed", [3, 4])
def test_a_tape_band_over_the_finger_shaft_widens_the_uncertainty(seed):
    # the band hides most of the proximal phalanx's straight shaft: the finger's edges
    # are then taken from next to the knuckle, where the flare tilts them; the answer
    # says so with a larger uncertainty
    plain, _ = render_finger(40.0, shape=(960, 1280), rng=seed, difficulty="clean", background_bgr=(60, 90, 60))
    taped, _ = render_finger(40.0, shape=(960, 1280), rng=seed, difficulty="clean", tape=True,
                             background_bgr=(60, 90, 60))
    m0, m1 = measure_angle(plain), measure_angle(taped)
    assert m0.status == m1.status == "ok", (m0.reason, m1.reason)
    assert m0.details["finger_edges_from_widths"] == 1.0 and m1.details["finger_edges_from_widths"] < 1.0
    assert m1.angle_unc_deg > 1.0 > m0.angle_unc_deg
    assert abs(m0.angle_deg - 40.0) < 1.0 and abs(m1.angle_deg - 40.0) < 2 * m1.angle_unc_deg


def _saved_photo(tmp_path, angle, rng, difficulty, transform=None):
    """A 1280x960 render written as a user's JPEG photo (the benchmark's photos): its path.
    ``transform`` (image -> image) is applied before saving: a mirrored photo, say."""
    img, _ = render_finger(angle, shape=(960, 1280), rng=rng, difficulty=difficulty, jpeg_quality=None,
                           palm_mm=NO_PALM)
    if transform is not None:
        img = np.ascontiguousarray(transform(img))
    path = tmp_path / "photo.jpg"
    cv2.imwrite(str(path), img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    return path


def _as_saved_photo(tmp_path, angle, rng, difficulty, transform=None):
    """The saved photo (``_saved_photo``) read back and measured as `flexcal measure`
    does: its row of the angles table."""
    from flexcal.measure import measure_file
    return measure_file(_saved_photo(tmp_path, angle, rng, difficulty, transform))[0]


def _assert_measured(tmp_path, angle, rng, difficulty, tol, transform=None, via=None):
    """The saved photo (``_saved_photo``), read back as `flexcal measure` reads it, is
    answered sure and within ``tol`` deg; and, with ``via``, on the silhouette found so
    (``details["via"]``, "first" for the first silhouette of the first segmentation)."""
    from flexcal.measure import measure_photo
    m, _, _ = measure_photo(_saved_photo(tmp_path, angle, rng, difficulty, transform))
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - angle) < tol, m.angle_deg
    if via is not None:
        assert m.details.get("via", "first") == via


def test_skin_of_the_walls_hue_but_darker_is_the_finger_not_the_walls_shadow(tmp_path):
    # light skin on a peach wall: the finger's colours look like the wall in shadow;
    # with them taken as shadow nothing finger-like is left, so they are the finger's
    angle = 12.577279926704417
    _assert_measured(tmp_path, angle, 628836723, "realistic", tol=1.5)


def test_half_a_finger_in_the_walls_shadow_colour_is_refused(tmp_path):
    # the lit top of the finger is in the wall's own colour and only its shaded half is
    # left: the answer would be 8 deg off, so an unsure answer is refused with the reason
    row = _as_saved_photo(tmp_path, 8.410134014515624, 375083758, "clean")
    assert row["status"] == "failed" and "wall's in shadow" in row["reason"]


@pytest.mark.parametrize("seed", [8, 9, 12])
def test_a_tape_band_over_the_finger_does_not_move_the_knuckle(seed):
    # the band's notch (or bump) used to draw the knuckle a finger width towards the
    # tip, putting the band inside the finger's window; the answers were 2-2.5 deg off
    angle = 20.0 + 5 * seed
    img, _ = render_finger(angle, shape=(960, 1280), rng=seed, difficulty="clean", tape=True, palm_mm=NO_PALM)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - angle) < 1.0


def test_a_shaded_rim_of_the_finger_is_not_taken_for_a_layer_on_it(tmp_path):
    # the finger's underside is darker skin; its colour, just past what counts as the
    # skin's own, was taken for a layer on some outline points and not on others, so
    # the edge line tilted: 2.6 deg off. A layer stands out from the skin more.
    angle = 79.9555883685009
    _assert_measured(tmp_path, angle, 2058286628, "clean", tol=1.0)


def test_the_finger_edge_line_is_aimed_from_all_of_its_window(tmp_path):
    # the sensor strip ends in the finger's window: the window's core held little skin
    # edge under it, and the line started there ran 2.8 deg off the finger's edge
    angle = 61.813210459480175
    _assert_measured(tmp_path, angle, 1674246220, "realistic", tol=1.0)


def test_forearm_colours_that_cut_the_finger_lengthwise_are_not_taken(tmp_path):
    # mirrored, this photo's first measurement is unsure, and the colours in which the
    # arm leaves the picture keep only the finger's lit half: a sure answer 9 deg off.
    # Where they cut the silhouette the colour fades (lit to shaded skin) rather than
    # stepping (skin to an object), so that silhouette is not taken
    angle = 9.363449349550967
    _assert_measured(tmp_path, angle, 612453171, "realistic", tol=1.5, transform=lambda im: im[:, ::-1],
                     via="9 colours")


def test_cut_contrast_tells_an_object_cut_off_from_a_finger_cut_in_two():
    from flexcal.vision.edges import cut_contrast
    rng = np.random.default_rng(3)
    img = np.full((200, 300, 3), (200, 200, 200), np.uint8)           # the wall
    yy = np.arange(200)[:, None] * np.ones((1, 300))
    skin = np.clip(np.array([90, 120, 190])[None, None, :] * (1.2 - (yy[..., None] - 60) / 100), 0, 255)
    img[60:120, :200] = skin[60:120, :200].astype(np.uint8)           # a finger, shaded downwards
    img[40:140, 200:280] = (200, 40, 200)                             # a box joined to it
    img = np.clip(img + rng.normal(0, 2, img.shape), 0, 255).astype(np.uint8)
    whole = np.zeros((200, 300), np.uint8)
    whole[60:120, :200] = 1
    whole[40:140, 200:280] = 1
    finger = whole.copy()
    finger[:, 200:] = 0                                 # the box cut off: a step in colour
    assert cut_contrast(img, whole, finger) > 30
    lit = finger.copy()
    lit[90:, :] = 0                                     # the finger cut along its shading
    assert cut_contrast(img, whole, lit) < 12


def test_a_knuckle_just_beyond_the_usual_range_is_not_replaced_by_the_next_joint(tmp_path):
    # mirrored, this finger's thin distal part puts its width near the tip at half the
    # finger's and the knuckle at 8.3 of those widths, beyond the range searched: the
    # best place within it was where the thin part meets the finger, answered sure 33
    # deg off. The midline splits far better beyond the range: refused, or measured there
    angle = 37.464357869321965
    row = _as_saved_photo(tmp_path, angle, 1711792829, "clean", transform=lambda im: im[:, ::-1])
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 1.5, row["angle_deg"]


@pytest.mark.parametrize("angle, rng, via", [(3.7064964957248616, 1855444348, "forearm's colours"),
                                             (41.84074509875122, 653852867, "first")])
def test_an_unsure_photo_of_a_cluttered_wall_is_measured_on_a_rebuilt_silhouette(tmp_path, angle, rng, via,
                                                                               found_without_a_palm):
    # posters on the wall use up the six colour clusters: the finger's silhouette takes
    # in some wall or loses its rim, and the measurement is unsure. Nine colours gave the
    # finger's silhouette when this test was written; in the first, the silhouette in the
    # forearm's colours, tried before them, now does. In the second, the forearm's
    # colours took the hand for 3x the finger's width (before the foreground's opening
    # was centred, 2026-11-28, they measured it, and the first silhouette was refused as
    # a bent second joint); nine colours measured it (42.3 deg) until 2026-11-29, when
    # the first silhouette's hand, whose midline had seemed bent by 6 deg between two
    # straight edges, stopped being refused for it: 42.5 deg, sure
    _assert_measured(tmp_path, angle, rng, "realistic", tol=1.5, via=via)


@pytest.mark.parametrize("angle, rng", [(74.63685589089647, 1385066308), (83.75929666211532, 423916129)])
def test_a_finer_segmentation_mostly_elsewhere_is_not_taken(tmp_path, angle, rng):
    # in finer colours these photos give a sure answer on another silhouette (the hand
    # without its finger, the shaded underside of the hand): 74 and 83 deg off; it
    # overlaps the first too little to be the same finger, and the photo stays refused
    row = _as_saved_photo(tmp_path, angle, rng, "hard")
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 5.0, row["angle_deg"]


def test_a_refusal_for_edges_without_a_line_says_so_in_words():
    # a tape band on a pale glove leaves a few edge points around it, no straight
    # line: the reason read "(+-inf deg)"
    from flexcal.measure import measure_file
    photo = Path(__file__).resolve().parents[2] / "datasets/sample/trial_02/images/step_06_050deg.jpg"
    row = measure_file(photo)[0]
    assert "inf" not in row["reason"], row["reason"]
    assert row["status"] != "failed" or "straight line" in row["reason"], row["reason"]


def test_a_finger_cut_short_by_a_band_is_refused_not_measured_straight(tmp_path):
    # an 83 deg bend; the tape band and the finger's lit side are in the wall's colours,
    # so the finger beyond the band hangs on the hand by a sliver and the finishing cuts
    # it off: what is left (hand and knuckle) measured "sure" 3.8 deg. The piece lies
    # right beyond the silhouette's "tip": the finger is cut short, and that is said
    row = _as_saved_photo(tmp_path, 83.20062408887179, 884762960, "hard")
    assert row["status"] == "failed" and "cut short" in row["reason"]


def test_a_piece_counts_as_cut_off_the_tip_only_ahead_of_it():
    from flexcal.vision.angle import _cut_short
    tip, ahead, wf = (100.0, 100.0), (1.0, 0.0), 20.0
    for (x0, y0), want in [((112, 95), True),      # just beyond the tip
                           ((112, 108), True),     # ahead, 34 deg off the axis
                           ((100, 114), False),    # beside it: a neighbouring finger
                           ((100, 108), True),     # right beside it: the finger beyond a band at the knuckle
                           ((80, 95), False),      # behind it
                           ((127, 95), True),      # 1.35 widths ahead: beyond a tape band
                           ((135, 95), False)]:    # more than 1.5 widths away
        piece = np.zeros((200, 200), bool)
        piece[y0:y0 + 10, x0:x0 + 10] = True
        assert (_cut_short(tip, ahead, piece, wf) is not None) == want, (x0, y0)


@pytest.mark.parametrize("angle, rng, turn", [(65.98032071996897, 986882917, cv2.ROTATE_180),
                                              (50.51187431985993, 919609400, cv2.ROTATE_90_CLOCKWISE),
                                              (33.19608453318753, 1604659906, cv2.ROTATE_90_COUNTERCLOCKWISE),
                                              (22.702980362023176, 908922372, cv2.ROTATE_90_CLOCKWISE)])
def test_a_stub_of_the_hand_cut_at_a_band_is_not_measured_straight(tmp_path, angle, rng, turn):
    # turned photos whose first silhouette is the hand up to the first tape band (in the
    # background's colours; the rest of the finger beyond it a part of its own, not
    # joined by any neck): the stub measured sure and straight, 31-65 deg off. The rest
    # of the finger lies right ahead of the stub's "tip". In the last, the stub is a
    # silhouette rebuilt from the forearm's colours (22 deg off): the finger beyond the
    # band was in the part, but apart from the stub
    row = _as_saved_photo(tmp_path, angle, rng, "hard", transform=lambda im: cv2.rotate(im, turn))
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 5, row


@pytest.mark.parametrize("angle, rng", [(46.40463666061759, 1757889693), (63.76381260098251, 819262446),
                                        (54.53978592725593, 54584990)])
def test_a_poster_behind_the_fingertip_in_the_arms_colour_clusters_is_split_off_at_its_edge(tmp_path, angle, rng):
    # cluttered walls: posters behind the fingertip join the silhouette, and in six
    # colour clusters they share one with the skin, its shade or the sensor's lead, so the
    # forearm's clusters bring them back (refused: "too little of the hand", "leaves the
    # picture in 2 places"). Grown from the arm's own colour to the strongest colour edge,
    # the finger is parted from the poster along its outline. (In the third, the poster
    # joined at the fingertip is so wide that the first measurement took it for the
    # finger: "too little of the hand" for a finger that wide. That width must not decide
    # whether the forearm's colours are worth trying.)
    _assert_measured(tmp_path, angle, rng, "realistic", tol=1.5)


def test_an_unsure_answer_on_the_silhouette_in_the_forearms_colours_does_not_count(tmp_path):
    # a dark hand against a dark box: the hand's shaded half went to the box, and with the
    # poster beside the finger parted off, the thin hand measured unsure at 1 deg for 12.5
    row = _as_saved_photo(tmp_path, 12.484372688340029, 412284311, "hard")
    assert row["status"] == "failed" or abs(row["angle_deg"] - 12.484372688340029) < 5, row


def test_the_arm_grown_from_its_colour_keeps_the_finger_and_leaves_the_wall():
    # on a plain photo, the silhouette rebuilt from the pixel-wise forearm region, grown
    # within the part or over the whole picture, is the first one less the sensor's strip
    # (another colour): nothing of the wall, nearly all of the hand and finger, and it
    # measures the bend
    from flexcal.vision.angle import _measure_silhouette, _segment
    from flexcal.vision.segment import forearm_colours, forearm_grown
    img, truth = render_finger(40.0, shape=SHAPE, rng=3, difficulty="clean", background="plain")
    work, f, seg = _segment(img)
    grown = forearm_grown(seg, work)
    assert [within is None for _, within in grown] == [False, True], "one crossing, grown two ways"
    mask = seg.mask.astype(bool)
    for keep, within in grown:
        alt, cut_off = forearm_colours(seg, keep, within)
        alt = alt.astype(bool)
        assert (alt & ~mask).sum() < 0.01 * mask.sum()
        assert (alt & mask).sum() > 0.85 * mask.sum()
        m = _measure_silhouette(work, f, alt.astype(np.uint8), seg.contrast, cut_off=cut_off)
        assert m.status == "ok", m.reason
        assert abs(m.angle_deg - truth.angle_deg) < 1.5


def test_a_finger_whose_lit_skin_is_in_the_walls_cluster_is_grown_back_from_the_arm(tmp_path):
    # a cluttered wall: the finger beyond its first tape band shares a colour cluster with
    # the wall, so the part is the hand and the finger up to the band, or a poster at the
    # tip widens it: refused. Grown from the arm's own colour over the whole picture,
    # pixel by pixel, the finger comes back up to its outline against the wall (in nine
    # colour clusters). (A second render, 54.2 deg rng 284666435, showed it in six; there
    # the silhouette is now the hand's shaded underside alone, too narrow to bridge the
    # band, and the photo is refused.)
    _assert_measured(tmp_path, 52.364373133001386, 1577787461, "realistic", tol=1.5,
                     via="9 colours; forearm's colours")


def test_a_side_of_the_silhouette_without_a_colour_step_is_not_the_fingers_edge(tmp_path):
    # tan skin against a tan box: the lit skin went to the box's colour cluster, and the
    # silhouette left is the shaded underside of the hand up to the first tape band, a
    # straight strip that measured sure at 1 deg for an 81 deg bend. Its upper side runs
    # along the shading on the skin: no colour step across it, so it is no edge (refused:
    # grown from the arm's colour, the hand floods the box)
    row = _as_saved_photo(tmp_path, 80.81814014519658, 1740952063, "hard")
    assert row["status"] == "failed" or abs(row["angle_deg"] - 80.81814014519658) < 1.5, row


def test_a_side_with_only_a_weak_colour_step_along_both_arms_is_not_the_fingers_edge(tmp_path):
    # a brown finger, the photo turned by 90 deg: the silhouette rebuilt from the arm's
    # colour is only the finger's and hand's lit half, and its inner side runs along the
    # shading, with median colour steps of 3.5 and 3.6 in the two arms' windows (the sure
    # answers on the benchmark's 600 renders: 5.3 and more on every side). It measured
    # sure at 15 deg for 38
    row = _as_saved_photo(tmp_path, 38.02800755691536, 361835457, "hard",
                          transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE))
    assert row["status"] == "failed" or abs(row["angle_deg"] - 38.02800755691536) < 5, row


@pytest.mark.parametrize("angle, rng, difficulty", [(36.84249304403988, 293973365, "clean"),
                                                    (2.6709327157127505, 924267260, "realistic"),
                                                    (65.43677852068998, 229025283, "realistic")])
def test_a_finger_whose_lit_side_is_in_the_walls_colour_is_measured_on_its_whole_outline(tmp_path, angle, rng,
                                                                                          difficulty):
    # the lit top of the finger or hand is in the wall's colour cluster, so a side of the
    # silhouette runs along the shading inside it: measured on it, sure and about 2 deg
    # off. That side crosses no colour step; unsure, the arm grown from its own colour
    # over the picture gives the finger and hand back up to their outline
    _assert_measured(tmp_path, angle, rng, difficulty, tol=1.0, via="forearm's colours")


def test_a_bend_beyond_any_knuckles_range_is_not_answered(tmp_path):
    # a purple glove beside posters, the photo turned by 90 deg: the arms found were not
    # the finger's and the hand's, and met at 154 deg (sure) for a 17 deg bend
    row = _as_saved_photo(tmp_path, 17.160138862129322, 1966244999, "hard",
                          transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_COUNTERCLOCKWISE))
    assert row["status"] == "failed" or abs(row["angle_deg"] - 17.160138862129322) < 5, row


def test_an_arm_grown_into_the_whole_wall_is_no_silhouette():
    # a wall close to the skin's colour lets the arm grown over the picture flood it; such
    # a region is no arm (and, covering the whole picture, has no distance to any edge:
    # the finishing's kernel sizes overflowed)
    from flexcal.vision.angle import _segment
    from flexcal.vision.segment import forearm_colours
    img, _ = render_finger(40.0, shape=SHAPE, rng=3, difficulty="clean", background="plain")
    _, _, seg = _segment(img)
    assert forearm_colours(seg, np.ones(seg.part.shape, bool), None) is None
    wall = ~cv2.dilate(seg.part, np.ones((9, 9), np.uint8)).astype(bool)
    assert forearm_colours(seg, wall | (seg.part > 0), None) is None


def test_a_finger_too_thin_to_measure_says_how_thin_for_any_photo_size():
    # a bent tube 3 px thick entering from the left of a 640 x 480 picture: the limit is
    # given as a share of the picture's long side (the same for the 1280 px photo it was
    # reduced from, and for a 320 px photo), and a larger photo would not help; only in
    # a photo so small that the limit is a few pixels would it
    from flexcal.vision.angle import _measure_silhouette
    mask = np.zeros((480, 640), np.uint8)
    cv2.polylines(mask, [np.array([[0, 240], [300, 240], [420, 380]], np.int32)], False, 1, thickness=3)
    work = np.full((480, 640, 3), 200, np.uint8)
    m = _measure_silhouette(work, 1.0, mask, 50.0)
    assert m.status == "failed" and "too thin (" in m.reason and "0.6% of the picture's long side, under 2.5%" in m.reason, m.reason
    assert "larger photo" not in m.reason
    m = _measure_silhouette(work[:240, :320], 1.0, mask[::2, ::2].copy(), 50.0)
    assert "too thin (" in m.reason and "under 2.5%" in m.reason, m.reason
    assert "larger photo" not in m.reason
    small = np.zeros((90, 120), np.uint8)
    cv2.polylines(small, [np.array([[0, 45], [60, 45], [85, 75]], np.int32)], False, 1, thickness=2)
    m = _measure_silhouette(work[:90, :120], 1.0, small, 50.0)
    assert "too thin (" in m.reason and "under 3.3%" in m.reason and "larger photo" in m.reason, m.reason


def _benchmark_photo(angle, rng, difficulty, transform=None, **params):
    """The benchmark's photo: a 1280x960 render (``params`` override its nuisances;
    ``transform``, image -> image, turns or mirrors it as the benchmark does) saved as
    JPEG q90 and read at half size, as `flexcal measure` reads it; and its truth."""
    img, truth = render_finger(angle, shape=(960, 1280), rng=rng, difficulty=difficulty, jpeg_quality=None,
                               **{"palm_mm": NO_PALM, **params})
    if transform is not None:
        img = np.ascontiguousarray(transform(img))
    _, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    return cv2.imdecode(buf, cv2.IMREAD_REDUCED_COLOR_2), truth


def _assert_refused_or_within(angle, rng, difficulty, tol, transform=None, **params):
    """The benchmark's photo (``_benchmark_photo``) is refused, or answered within ``tol``
    deg of ``angle``: a check that must not be confidently wrong."""
    m = measure_angle(_benchmark_photo(angle, rng, difficulty, transform, **params)[0])
    assert m.status == "failed" or abs(m.angle_deg - angle) < tol, (m.angle_deg, m.status, m.details.get("via"))


def _measured_with_kmeans_seed(angle, rng, difficulty, seed):
    """The benchmark's photo (``_benchmark_photo``) measured with k-means started from
    another random seed (every segmentation, as ``benchmarks/vision.py --kmeans-seed``):
    another draw of the colour clusters, as another photo of the same scene could give."""
    from flexcal.vision import angle as vision_angle
    work, _ = _benchmark_photo(angle, rng, difficulty)
    default, vision_angle.KMEANS_SEED = vision_angle.KMEANS_SEED, seed
    try:
        return vision_angle._measure_contour(work)
    finally:
        vision_angle.KMEANS_SEED = default


@pytest.mark.parametrize("angle, rng", [(4.656597514583068, 1090085296), (49.049442620569614, 1180153398)])
def test_a_photo_refused_on_one_draw_of_its_colours_is_measured_when_two_others_agree(monkeypatch, angle, rng):
    # held-out realistic renders (seed 40000 render 4, seed 140000 render 52, as
    # rendered): refused on k-means' first random start; the next two starts both
    # measure them, sure, and agree
    from flexcal.vision import angle as vision_angle
    work, _ = _benchmark_photo(angle, rng, "realistic")
    monkeypatch.setattr(vision_angle, "OTHER_DRAWS", 0)
    assert measure_angle(work).status == "failed"
    monkeypatch.undo()
    m = measure_angle(work)
    assert m.status == "ok" and m.details["via"].startswith("other draws of the colours"), m.reason
    assert abs(m.angle_deg - angle) < 1.5, m.angle_deg


def test_a_photo_refused_on_one_draw_is_not_measured_when_the_other_draws_disagree(monkeypatch):
    # the same photo, with the second of the other draws made to disagree: refused
    from flexcal.vision import angle as vision_angle
    work, _ = _benchmark_photo(4.656597514583068, 1090085296, "realistic")
    draw = vision_angle._measure_draw

    def disagreeing(segmented, seed, **kwargs):
        m = draw(segmented, seed, **kwargs)
        if seed == vision_angle.KMEANS_SEED + 2:
            m.angle_deg += 3 * np.hypot(m.angle_unc_deg, m.angle_unc_deg)
        return m

    monkeypatch.setattr(vision_angle, "_measure_draw", disagreeing)
    assert measure_angle(work).status == "failed"


def test_the_blurred_edge_of_a_box_is_not_taken_for_a_thin_finger():
    # the benchmark's hard render 4 (seed 2026), black glove against a grey box: with
    # k-means' seed 3 the band of blur along the box's edge beside the hand, 1.2 % of the
    # picture wide, was the silhouette, and measured as a finger bent 7 deg (truly 75),
    # confidence 0.73
    m = _measured_with_kmeans_seed(74.63685589089647, 1385066308, "hard", seed=3)
    assert m.status == "failed" and "too thin (" in m.reason, (m.angle_deg, m.reason)


@pytest.mark.parametrize("angle, rng", [(83.65394142656997, 1964350263), (32.46144935120587, 225527721),
                                        (9.581793037862036, 686687566)])
def test_a_strip_barely_thicker_than_a_box_edge_is_not_taken_for_a_finger(tmp_path, angle, rng):
    # held-out hard renders (seeds 70000, 60000 and 70000: renders 58, 59 and 65) turned
    # by 90 deg: the only silhouette measured sure was a strip 2.0-2.1 % of the picture
    # wide (the sensor's lead, a piece of its red strip, a strip of the finger), straight,
    # 9-83 deg off. The benchmark's fingers are 2.7 % wide or more
    row = _as_saved_photo(tmp_path, angle, rng, "hard", transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE))
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 5, row


def test_a_stub_ending_at_a_band_is_cut_short_in_its_own_tips_colours():
    # the benchmark's hard render 74 (seed 5000), a finger bent 54 deg: with k-means'
    # seed 2 the silhouette rebuilt in the forearm's colours was the hand up to the
    # first tape band, measured sure and straight (0.2 deg). The finger beyond the band
    # lies just ahead of that stub's end, in the stub's own tip colours (not in those of
    # the first part's tip, a box joined to the hand)
    m = _measured_with_kmeans_seed(54.415127118066295, 251582544, "hard", seed=2)
    assert m.status != "ok", (m.angle_deg, m.reason)


@pytest.mark.parametrize("angle, rng, seed", [(71.7540310509782, 1216593277, 1),
                                              (54.23149151424852, 284666435, 6)])
def test_a_finger_cut_short_is_measured_on_finer_colours_that_hold_the_rest_of_it(monkeypatch, angle, rng, seed):
    # the benchmark's realistic renders 71 and 48 (seed 5000) on other k-means draws: a
    # tape band in the background's colours cut the finger, and the rest of it beyond
    # the band lay ahead of the silhouette's "tip" (refused, cut short). Segmented in
    # finer colours the band joins them: that silhouette holds the first and the rest of
    # the finger, and measures sure (it overlaps the first too little to count as
    # agreeing with it otherwise: 0.64 and 0.22 of the union). (Whether the next draw's
    # finer colours give it again is another check: on k-means' seed 1, render 71's do
    # not, and the photo is refused)
    from flexcal.vision import angle as vision_angle
    monkeypatch.setattr(vision_angle, "_confirmed_in_finer_colours", lambda *args: True)
    m = _measured_with_kmeans_seed(angle, rng, "realistic", seed=seed)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.0, (m.angle_deg, m.reason)


@pytest.mark.parametrize("turn", [lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE),
                                  lambda im: cv2.rotate(im, cv2.ROTATE_180),
                                  lambda im: cv2.rotate(im, cv2.ROTATE_90_COUNTERCLOCKWISE), np.fliplr],
                         ids=["r90", "r180", "r270", "mirrored"])
def test_an_oval_poster_joined_to_the_finger_between_two_bands_is_not_measured(turn):
    # seed 5000 hard render 15, bent 13.5 deg: two tape bands in the wall's colours cut
    # a purple glove's finger into pieces, and a thin oval poster, its end on the
    # picture's edge, joins the middle piece. The silhouettes rebuilt in the poster's
    # colours are the oval alone, 2.65 % of the picture wide and straight; with the
    # glove's piece just ahead of its end left uncounted (the part's tip colours, which
    # the oval does not hold) they measured 0.1-0.6 deg, sure
    a = 13.523055417171294
    img, _ = _benchmark_photo(a, 20277394, "hard", transform=turn)
    m = measure_angle(img)
    assert m.status == "failed" or abs(m.angle_deg - a) < max(3.0, 2 * m.angle_unc_deg), (m.angle_deg, m.reason)


def test_a_stub_joined_to_the_rest_of_the_finger_by_a_thin_rim_is_cut_short(tmp_path):
    # the same render turned by 90 deg: the stub of the hand up to the band measured
    # sure, 54 deg off; the finger beyond the band was joined to it only by its rim, a
    # strip a few pixels wide in the tip's colours running on across the band
    row = _as_saved_photo(tmp_path, 54.415127118066295, 251582544, "hard",
                          lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE))
    assert row["status"] != "ok", (row["angle_deg"], row["reason"])


def test_a_finger_far_wider_in_its_window_than_at_its_tip_is_not_taken(tmp_path):
    # the benchmark's clean render 38 (seed 2026): one reading found the finger 1.7x as
    # wide in its window as near its tip (its tip's width too small) and was 2.5 deg off,
    # sure; a finger widens about 1.3x. Without it, another reading is taken
    _assert_measured(tmp_path, 37.464357869321965, 1711792829, "clean", tol=1.0)


def test_finer_colours_part_a_poster_off_a_silhouette_that_was_no_finger(tmp_path):
    # the benchmark's realistic render 95 (seed 2026): in six colour clusters the
    # finger's silhouette took in a poster at its tip ("too little of the hand"); in
    # nine the poster is parted off, a much smaller silhouette (overlap 0.65), which
    # measures sure and right
    _assert_measured(tmp_path, 54.6273365148081, 271636636, "realistic", tol=1.0, via="9 colours; forearm's colours")


def test_finer_colours_are_tried_when_the_first_found_no_elongated_object(tmp_path):
    # the benchmark's hard render 52 (seed 5000), a grey glove and sleeve against a
    # lilac wall with posters: in six colour clusters nothing finger-like entered the
    # picture; in nine the sleeve is a part of its own, and the measurement on it
    # (the arm grown over the picture) is sure and right
    _assert_measured(tmp_path, 44.5805758330246, 115769261, "hard", tol=2.0, via="9 colours; forearm's colours")


@pytest.mark.parametrize("seed", [1, 7920])
def test_finer_colours_within_a_strip_too_thin_for_a_finger_are_the_strip_again(seed):
    # the benchmark's hard render 4 (seed 2026), black glove against a grey box: with
    # k-means' seed 1 the silhouette was the band along the box's edge, too thin; the
    # finer colours found a silhouette mostly within that band, measured 3 deg (truly
    # 75), sure. With seed 7920 the finer silhouette took in 91 % of the band and the
    # shading along it, three times its size: the band again, measured 3.8 deg, sure
    m = _measured_with_kmeans_seed(74.63685589089647, 1385066308, "hard", seed=seed)
    assert m.status != "ok", (m.angle_deg, m.reason)


def test_a_box_joined_to_the_hand_and_reaching_the_edge_is_parted_off_not_measured_with(found_without_a_palm):
    # a bent finger and its hand entering from the left, and a white box joined to the
    # hand's underside that reaches the picture's bottom edge: the silhouette of all
    # three leaves the picture in two places, and one side of the "hand" may then be the
    # box's edge. It is not measured sure; the photo is, on the hand and finger alone
    from flexcal.vision.angle import _measure_silhouette

    def photo(box):
        work = np.full((480, 640, 3), (170, 185, 200), np.uint8)
        mask = np.zeros((480, 640), np.uint8)
        if box:
            cv2.rectangle(work, (60, 250), (100, 479), (235, 240, 245), -1)
            cv2.rectangle(mask, (60, 250), (100, 479), 1, -1)
        for img, value in ((work, (70, 110, 170)), (mask, 1)):
            cv2.line(img, (-50, 220), (330, 220), value, 70)
            cv2.line(img, (330, 220), (490, 340), value, 56)
        return cv2.GaussianBlur(work, (5, 5), 0), mask

    truth = np.degrees(np.arctan2(120, 160))
    work, mask = photo(box=False)
    m = _measure_silhouette(work, 1.0, mask, 50.0)
    assert m.status == "ok" and abs(m.angle_deg - truth) < 0.5, (m.angle_deg, m.reason)
    work, mask = photo(box=True)
    m = _measure_silhouette(work, 1.0, mask, 50.0)
    assert m.status != "ok" and "leaves the picture in 2 places" in m.reason, m.reason
    m = measure_angle(work)
    assert m.status == "ok" and abs(m.angle_deg - truth) < 0.5, (m.angle_deg, m.reason)


def test_a_silhouette_joined_to_a_box_reaching_the_edge_does_not_move_the_knuckle_unseen():
    # the benchmark's hard render 59 (seed 2026), a black glove bent 15 deg over a white
    # box that reaches the picture's bottom edge: with k-means' seed 2 the finer colours'
    # silhouette held the hand and the box, left the picture in two places, and its sure
    # reading put the knuckle at the bent second joint, 21 deg off
    m = _measured_with_kmeans_seed(14.595159612152067, 30642108, "hard", seed=2)
    assert m.status != "ok" or abs(m.angle_deg - 14.595159612152067) < 5, (m.angle_deg, m.reason)


def test_a_stub_ending_at_a_band_as_wide_as_the_finger_is_cut_short():
    # the benchmark's hard render 76 (seed 5000), a black glove bent 47 deg against a
    # dark box: with k-means' seed 4 the silhouette was a stub of the hand up to a tape
    # band, measured 4 deg, sure; the rest of the finger starts 1.4 finger widths
    # beyond the stub's end (the band's width)
    m = _measured_with_kmeans_seed(46.651783703328775, 980937715, "hard", seed=4)
    assert m.status != "ok" or abs(m.angle_deg - 46.651783703328775) <= 2 * m.angle_unc_deg, \
        (m.angle_deg, m.angle_unc_deg)


def test_a_stub_cut_at_a_band_beside_its_tip_is_cut_short():
    # held-out hard render 3 of seed 30000, bent 85 deg with the finger's band at the
    # knuckle: the band, in the wall's colours, cut the finger off, and the silhouette was
    # the hand and a stub of the finger up to the band, read straight (0.4 deg, sure, in
    # four of five turns). The rest of the finger starts 0.4 of the stub's widths from
    # its "tip", but beside it (79 deg from straight ahead), bent away with the knuckle
    _assert_refused_or_within(84.56161133416009, 1701775145, "hard", 3.0, palm_mm=8.344572467186842)


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (84.56161133416009, 1701775145, 8.344572467186842, cv2.ROTATE_90_CLOCKWISE),
    (25.95091145042999, 945078163, 9.88953459297312, cv2.ROTATE_180),
    (3.309808740002712, 938219023, 9.388607010440904, cv2.ROTATE_90_COUNTERCLOCKWISE)],
    ids=["stub of the hand", "nitrile glove", "second joint"])
def test_an_answer_in_finer_colours_that_the_next_draw_does_not_give_is_not_taken(angle, rng, palm_mm, turn):
    # held-out hard renders, turned, answered sure in nine colours only: 30000 render 3,
    # the hand and a stub of the finger cut square at a band (0.7 deg for 84.6); 30000
    # render 50, a blue nitrile glove (3.2 for 26.0); 40000 render 95, a black glove with
    # the knuckle put on its bent second joint (32.4 for 3.3). On k-means' next random
    # start the nine colours refuse the first two and read the third right
    _assert_refused_or_within(angle, rng, "hard", 5.0, transform=lambda im: cv2.rotate(im, turn), palm_mm=palm_mm)


@pytest.mark.parametrize("angle, rng, palm_mm, turn", [
    (87.12051964421049, 1240215369, 6.409950410578659, cv2.ROTATE_180),
    (63.475606515560884, 1910574174, 7.1605648661240595, cv2.ROTATE_90_CLOCKWISE),
    (72.73279432289657, 1367305194, 6.009616628564357, cv2.ROTATE_180)],
    ids=["short finger", "forearm's colours", "parted"])
def test_a_finger_arm_whose_fingertip_lies_far_off_its_direction_is_not_the_fingers(angle, rng, palm_mm, turn):
    # held-out hard renders of seed 170000, turned, large bends read as straight, sure:
    # render 22 (3.4 deg for 87.1: a short finger, its tip in shadow, its knuckle nearer
    # the tip than the range searched, both arms put on the hand), render 32 (2.7 for
    # 63.5, rebuilt in the forearm's colours) and 53 (3.7 for 72.7, parted from another
    # finger). Seen from the arm taken for the finger, the fingertip lay 46-53 deg off it
    _assert_refused_or_within(angle, rng, "hard", 5.0, transform=lambda im: cv2.rotate(im, turn), palm_mm=palm_mm)


@pytest.mark.parametrize("pip", [0.0, 25.0, 45.0])
def test_a_finger_with_its_second_joint_bent_keeps_its_tip_ahead_of_its_arm(pip):
    # a clean render with the second joint bent up to the hard preset's 45 deg (the third
    # by 0.7 times that more): the fingertip stays within the bound of the finger's arm,
    # and the knuckle's bend is measured
    from flexcal.vision.angle import TIP_OFF_ARM_DEG
    img, t = render_finger(30.0, shape=(480, 640), rng=7, difficulty="clean", pip_deg=pip)
    m = measure_angle(img)
    assert m.status != "failed", m.reason
    assert m.details["tip_off_arm_deg"] < TIP_OFF_ARM_DEG - 5.0, m.details["tip_off_arm_deg"]
    assert abs(m.angle_deg - t.angle_deg) <= 3.0 * max(m.angle_unc_deg, 1.0), (m.angle_deg, t.angle_deg)


def test_a_knuckle_sought_beyond_the_usual_range_keeps_the_fingertip_near_the_fingers_line():
    # held-out 210000 hard 31 turned by 90 deg: two fingertips side by side; within the
    # usual range the arms were refused, and the knuckle sought further (9.6 widths) put
    # both arms on the hand: 3.0 deg for 81.4, sure, the tip 33 deg off the finger's arm
    # (under the 40 allowed for a bent second joint; right answers of that search: 12.5)
    _assert_refused_or_within(81.3619308649253, 807033805, "hard", 5.0,
                              transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE), palm_mm=8.35289932296364)


def test_a_sure_answer_is_read_again_without_a_thick_piece_in_other_colours():
    # held-out 230000 hard 66: a poster of another colour joined at the fingertip made the
    # finger longer, and the knuckle, sought so many widths from the tip, was put on the
    # second joint: 49.4 deg for 35.6, sure, in all five turns; rebuilt in the forearm's
    # colours (the poster left out), 37.4-38.5, sure
    _assert_refused_or_within(35.63610948559809, 1079186030, "hard", 5.0, palm_mm=7.5333117383934045)


def test_a_silhouette_rebuilt_in_the_colours_of_another_objects_crossing_is_not_taken():
    # held-out 220000 hard 82 turned by 90 deg: the part also crosses the picture's edge
    # where a blurred ellipse on the wall is cut by it; rebuilt in that crossing's
    # colours, the silhouette is the ellipse alone (8 % of the silhouette), measured as a
    # straight finger, sure: 3.7 deg for 62.5
    _assert_refused_or_within(62.53266203194038, 1979130648, "hard", 5.0,
                              transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE),
                              palm_mm=5.892033972202419)

def _tip_of(mask):
    """Where ``_outline_chains`` puts the fingertip on a silhouette, (x, y)."""
    from flexcal.vision.angle import _outline_chains
    chains, why = _outline_chains(mask)
    assert chains is not None, why
    return chains[0][0]


def test_the_fingertip_of_a_finger_curled_back_towards_the_hand_is_its_end_not_the_bends_corner():
    # the hand leaves the picture at its bottom edge; the finger bends by 90 deg at the
    # knuckle and again at its second joint, back towards the hand: in a straight line
    # the knuckle's outer corner is farther from where the hand leaves the picture than
    # the fingertip (held-out 200000 hard 6: the second joint's outer side taken for the
    # tip, 5.3 deg for 83)
    mask = np.zeros((480, 640), np.uint8)
    cv2.polylines(mask, [np.array([[420, 479], [420, 120], [300, 120], [300, 250]])], False, 1, thickness=40)
    cv2.circle(mask, (300, 250), 20, 1, -1)
    corner, end = np.array([290.0, 100.0]), np.array([300.0, 270.0])
    assert np.linalg.norm(corner - [420, 479]) > np.linalg.norm(end - [420, 479])    # (the trap is set)
    tip = _tip_of(mask)
    assert np.linalg.norm(tip - [300, 250]) <= 21 and tip[1] >= 245, tip    # on the finger's round end


def test_a_fingertip_touching_the_pictures_edge_is_still_the_silhouettes_end():
    # the hand leaves the picture at its left edge and the finger, bent down, touches
    # the bottom edge with its tip: that touch is no place where the silhouette leaves
    # the picture, and along the silhouette the tip is still the farthest from the hand
    mask = np.zeros((480, 640), np.uint8)
    cv2.polylines(mask, [np.array([[0, 200], [300, 200], [330, 460]])], False, 1, thickness=40)
    cv2.circle(mask, (330, 462), 20, 1, -1)
    assert mask[479].any()
    tip = _tip_of(mask)
    assert np.linalg.norm(tip - [330, 462]) <= 21 and tip[1] >= 455, tip    # on the finger's round end


@pytest.mark.parametrize("angle, rng, palm_mm", [(83.0802614460078, 2029012234, 8.746252046317526),
                                                  (37.556080050342366, 1895625743, 6.494403148475232)],
                         ids=["curled back", "two fingertips"])
def test_the_fingertip_moves_to_a_free_end_only_from_a_fingers_side(angle, rng, palm_mm):
    # held-out 200000 hard 6 turned by 90 deg: a bend of 83 deg with the second joint bent
    # by 35; the outer side of the second joint was taken for the fingertip and the
    # knuckle put on the hand: 5.3 deg, in all four turns (unsure, but answered). And
    # 5000 hard 87 turned by 90: two fingertips side by side, refused as too wide for one
    # finger; with its tip moved to the farther one's end, the nearer tip's point being
    # short of that end by half a width, it read 44.7 deg for 37.6, sure
    _assert_refused_or_within(angle, rng, "hard", 5.0, transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE),
                              palm_mm=palm_mm)


def test_a_finger_half_again_as_wide_in_its_window_as_at_its_tip_is_not_taken():
    # the benchmark's hard render 30 (seed 2026), a finger bent 15 deg: with k-means'
    # seed 4 one reading found the finger 1.48x as wide in its window as near its tip
    # and measured 22 deg, sure (sure answers on the benchmarks go up to 1.4x)
    truth = 15.411516371639049
    m = _measured_with_kmeans_seed(truth, 381868374, "hard", seed=4)
    assert m.status != "ok" or abs(m.angle_deg - truth) <= 2 * m.angle_unc_deg, (m.angle_deg, m.angle_unc_deg)
    if m.status == "ok":
        assert m.details["finger_window_width"] <= 1.45


@pytest.mark.parametrize("angle", [20.0, 55.0, 85.0])
def test_a_small_finger_in_the_picture_is_still_measured(angle):
    # at half the renderer's usual size in a 640 x 480 picture the finger is 2.7-3.5 % of
    # the picture's long side (the benchmark's smallest): above the limit, and measured,
    # less precisely (half the pixels across the finger) but as its uncertainty says
    img, t = render_finger(angle, shape=(480, 640), rng=int(angle), difficulty="clean", scale=0.5)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - t.angle_deg) <= 2 * m.angle_unc_deg and m.angle_unc_deg < 1.5


def test_a_strip_of_shaded_skin_left_by_a_wall_of_the_skins_colour_is_refused_with_that_cause():
    # the demo's trial 3 at 20 deg: light skin against a wall of nearly its colour. The
    # skin went to the wall's colours and the silhouette is the finger's shaded
    # underside, a strip 2.3 % of the picture wide along the finger and hand (it was
    # refused as "as wide as the hand", with a cutting mat in front of the hand named as
    # a cause); the reason must name the strip and the fix, a background of another colour
    from flexcal.measure import measure_file
    photo = Path(__file__).resolve().parents[2] / "datasets/sample/trial_03/images/step_03_020deg.jpg"
    row = measure_file(photo)[0]
    if row["status"] == "ok":
        assert abs(row["angle_deg"] - 20) < 2, row
    else:
        assert "strip" in row["reason"] and "background of another colour" in row["reason"], row["reason"]


def test_a_blob_joined_to_the_fingertip_does_not_set_the_fingers_width():
    # the finger's shadow on a dark box beside its tip, joined to the silhouette, is no
    # tube: its pairs do not face across. Its widths made the finger wider than it is
    # (1.6x in the render below), and the hand "as wide as the finger"
    from flexcal.vision.angle import _midline, _outline_chains, _tip_width
    mask = np.zeros((480, 640), np.uint8)
    mask[200:250, 0:300] = 1                              # the hand, leaving the picture
    cv2.rectangle(mask, (262, 200), (291, 400), 1, -1)    # the finger, 30 px wide
    cv2.circle(mask, (276, 400), 15, 1, -1)               # its round tip
    for blob in (None, [[262, 370], [230, 405], [276, 415]], [[262, 375], [235, 410], [276, 415]]):
        m = mask.copy()
        if blob is not None:
            cv2.fillPoly(m, [np.array(blob)], 1)          # a lump beside the tip
        _, width, s, facing, _, _ = _midline(*_outline_chains(m)[0][:2])
        wf, share = _tip_width(width, s, facing)
        assert abs(wf - 29.0) < 1.5 and share > 0.5, (blob, wf, share)


def test_a_finger_whose_tip_is_joined_to_its_shadow_is_measured(tmp_path):
    # dark skin over a dark red box: the finger's shadow on it joins the tip; the width
    # taken there (52 px for 34) made the hand look as thin as the finger, and refused
    _assert_measured(tmp_path, 65.13488052389076, 395976980, "realistic", tol=1.0)


def test_two_fingers_joined_at_their_bases_are_not_a_blob_at_a_fingertip(tmp_path):
    # a black glove, the next finger beside the index, both tips cut off by a poster:
    # what is left of the two fingers is the silhouette's "tip". The tube after it is
    # the hand, and a width taken there measured the hand as a straight finger, 22 deg off
    row = _as_saved_photo(tmp_path, 24.449095905767745, 30392184, "hard",
                          transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE))
    assert row["status"] == "failed" or abs(row["angle_deg"] - 24.449095905767745) < 5, row


def test_sure_readings_of_one_silhouette_that_disagree_are_refused(tmp_path):
    # a black glove bent at the second joint (35 deg) more than at the knuckle (15 deg),
    # turned upside down: a silhouette rebuilt in the forearm's colours took in a piece
    # of a white sheet beside the knuckle and measured the second joint, sure, 21 deg
    # off; the knuckle sought further on the finer silhouette gave 14.1 deg, also sure
    row = _as_saved_photo(tmp_path, 14.595159612152067, 30642108, "hard",
                          transform=lambda im: cv2.rotate(im, cv2.ROTATE_180))
    assert row["status"] == "failed" or abs(row["angle_deg"] - 14.595159612152067) < 5, row


_UNSURE = AngleMeasurement(angle_deg=16.3, angle_unc_deg=1.2, confidence=0.4, status="low_confidence")
_SURE = AngleMeasurement(angle_deg=24.8, angle_unc_deg=1.7, confidence=1.0, status="ok")


@pytest.mark.parametrize("answer, other, refused", [
    # (found on held-out 80000 realistic 90 turned by 90 deg: 16.3 deg for 6.5, unsure, at
    # low contrast, where the forearm's colours and the finer ones gave 5.4-7.6, unsure;
    # since the foreground's opening was centred all its readings are 6-8 deg)
    (_UNSURE, AngleMeasurement(angle_deg=6.4, angle_unc_deg=1.0, confidence=0.3, status="low_confidence"), True),
    # a finer silhouette that lost its rims, sure (50000 hard 28 upside down: 92.2 for an
    # unsure 81.6, not taken: it lost its rims)
    (_UNSURE, AngleMeasurement(angle_deg=27.0, angle_unc_deg=0.5, confidence=1.0, status="ok"), True),
    (_UNSURE, AngleMeasurement(angle_deg=17.0, angle_unc_deg=1.0, confidence=0.3, status="low_confidence"), False),
    (_UNSURE, failed("the finger's edge is hidden on one side where its direction is measured"), False),
    # a sure answer in finer colours, and a sure reading of the first silhouette far from
    # it (2026 hard 61 turned by 270 deg on k-means' third draw: 24.8 for 20.5, and 0.9)
    (_SURE, AngleMeasurement(angle_deg=0.9, angle_unc_deg=1.2, confidence=1.0, status="ok"), True),
    # ... an unsure one far from it is a guess the sure answer replaces
    (_SURE, AngleMeasurement(angle_deg=0.9, angle_unc_deg=1.2, confidence=0.3, status="low_confidence"), False),
    (_SURE, AngleMeasurement(angle_deg=25.8, angle_unc_deg=1.6, confidence=1.0, status="ok"), False),
])
def test_an_answer_that_another_reading_contradicts_is_refused(monkeypatch, answer, other, refused):
    # an unsure answer is a guess; another reading of the photo (another silhouette of
    # it, sure or not) far from it makes it a guess between them. A sure answer is
    # refused only when another sure reading contradicts it
    from flexcal.vision import angle

    def readings_of_the_photo(segmented, readings, seed=None, confirm_finer=True):
        readings += [answer, other]
        return answer
    monkeypatch.setattr(angle, "_measure_segmentations", readings_of_the_photo)
    m = angle._measure_draw(None, angle.KMEANS_SEED)
    if refused:
        assert m.status == "failed" and "readings of the silhouette disagree" in m.reason, m.reason
    else:
        assert m is answer


def test_a_sure_answer_in_finer_colours_that_the_first_silhouette_contradicts_is_refused():
    # the benchmark's hard render 61 of seed 2026 (its palm), turned by 270 deg: the first
    # draw of the colours is refused (the forearm's colours 25.8 deg, the first
    # silhouette a sure 0.9); on the third, nine colours give 24.8 for 20.5, sure, against
    # the same 0.9, and the other draws took it
    img, _ = _benchmark_photo(20.53638050416727, 1427695350, "hard", palm_mm=9.74729815319402,
                              transform=lambda im: cv2.rotate(im, cv2.ROTATE_90_COUNTERCLOCKWISE))
    m = measure_angle(img)
    assert m.status == "failed" and "readings of the silhouette disagree" in m.reason, (m.angle_deg, m.reason)


@pytest.mark.parametrize("seed,angle,difficulty", [
    (0, 15.0, "clean"), (1, 60.0, "clean"), (5, 15.0, "clean"), (7, 60.0, "clean"),
    # parted, this kept frayed strands along the parting and "forked"; finished as a
    # silhouette is (thin attachments opened off), it measures
    (1198865692, 81.5475, "realistic"),
    # a realistic render parted in six colours (another, 64.0 deg rng 1289101765, is
    # refused as two fingers since the foreground's opening was centred)
    (686732316, 71.9892, "realistic"),
])
def test_the_front_of_two_overlapping_fingers_is_measured(seed, angle, difficulty):
    # the next finger, bent further, lies behind the index: the silhouette is both
    # together (refused before as "as wide as the hand"). Parted at the index's edge
    # across the finger behind, the index and hand measure as one finger would
    img, _ = render_finger(angle, shape=(960, 1280), rng=seed, difficulty=difficulty, other_finger=True,
                           palm_mm=NO_PALM)
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert "parted from another finger" in m.details.get("via", "")
    assert abs(m.angle_deg - angle) < 1.5


@pytest.mark.parametrize("angle,rng,difficulty,turn", [
    # a pen with a dark rim taken for the finger: the rim parted off
    (79.13338586488884, 818083534, "hard", None),
    # one finger bent at its second joint: its end parted off, a stub kept
    (88.31962480522836, 391113570, "hard", None),
    # the parting frayed the tip: the finger's width, and its window, too small
    (55.03050474646171, 1941841597, "hard", None),
    # the front finger's tip parted off: the one behind measured, 12 deg off
    (14.603714768795754, 1965511984, "hard", None),
    # one finger, a stub of the hand below a band: the wall grew over most of it, and a
    # sliver along its side measured straight (51 deg off)
    (54.23149151424852, 284666435, "realistic", cv2.ROTATE_90_COUNTERCLOCKWISE),
])
def test_a_parting_of_two_fingers_that_misleads_is_not_taken(tmp_path, angle, rng, difficulty, turn):
    # renders of the benchmark (seeds 2026 and 5000) on which parting the silhouette at
    # an inner edge gave a sure answer 12 to 87 deg off, before the checks on the parting
    # (the silhouette mostly kept), the parted piece (thick as a finger, along one side
    # of the finger's window) and the reading (no doubts, the finger as wide in its
    # window as near its tip)
    row = _as_saved_photo(tmp_path, angle, rng, difficulty,
                          None if turn is None else (lambda im: cv2.rotate(im, turn)))
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 3, row


def test_the_finger_behind_kept_by_a_parting_is_not_measured():
    # seed 5000 hard 50 on k-means draw 7920: the index (with the sensor) in front of the
    # middle finger bent 23 deg further. One parting removed the index from its knuckle
    # on, cut across where the growths met, and kept the finger behind with the hand: its
    # bend, 75 deg, measured sure. That cut is the outer side of the bend measured
    angle = 52.417781107192404
    m = _measured_with_kmeans_seed(angle, 1335539867, "hard", seed=7920)
    assert m.status != "ok" or abs(m.angle_deg - angle) < 5, (m.angle_deg, m.reason)


def test_a_parting_on_the_outer_side_of_the_bend_is_told_from_one_along_the_finger():
    from flexcal.vision.angle import _outer_side_parted
    from flexcal.vision.measurement import Arm
    # a bend of 60 deg at (300, 200): the hand comes from the left, the finger goes down
    # to the right; the finger's silhouette is 30 px wide
    kept = np.zeros((480, 640), np.uint8)
    cv2.line(kept, (0, 200), (300, 200), 1, 30)
    tip = (300 + int(200 * np.cos(np.radians(60))), 200 + int(200 * np.sin(np.radians(60))))
    cv2.line(kept, (300, 200), tip, 1, 30)
    hand_dir, finger_dir = np.array([-1.0, 0.0]), np.array([np.cos(np.radians(60)), np.sin(np.radians(60))])
    m = AngleMeasurement(angle_deg=60.0, vertex=(300.0, 200.0),
                         proximal=Arm(np.array([200.0, 200.0]), hand_dir, 100.0),
                         distal=Arm(np.array([350.0, 287.0]), finger_dir, 100.0),
                         details={"finger_width_px": 30.0})
    # another finger removed along the inside of the bend (beneath the finger): no
    removed = np.zeros_like(kept)
    cv2.line(removed, (250, 235), (380, 420), 1, 25)
    removed &= ~kept
    assert not _outer_side_parted(kept > 0, removed > 0, m, 1.0)
    # the front finger removed from the knuckle on, over the bend's outer side: yes
    removed = np.zeros_like(kept)
    cv2.circle(removed, (300, 200), 60, 1, -1)
    removed[kept > 0] = 0
    removed[200:, :] = 0
    assert _outer_side_parted(kept > 0, removed > 0, m, 1.0)


def _drawn_photo(tmp_path, angle, rng, transform=None):
    """A cluttered drawing saved as a JPEG photo (``transform``ed first, if given),
    measured as `flexcal measure` does: its row of the angles table."""
    from flexcal.measure import measure_file
    img, _ = draw_finger(angle, rng=rng, cluttered=True)
    path = tmp_path / "photo.jpg"
    cv2.imwrite(str(path), np.ascontiguousarray(img if transform is None else transform(img)),
                [cv2.IMWRITE_JPEG_QUALITY, 90])
    return measure_file(path)[0]


def test_a_sliver_parted_off_two_fingers_is_not_measured_as_the_finger(tmp_path):
    # a drawn index (23 deg) with the middle finger behind it, bent further, mirrored:
    # parted at an inner edge, the kept piece was a sliver along the index's back (a fifth
    # of the two fingers' width near the tip) and measured straight, sure, 22.6 deg off
    # (the cluttered benchmark suite of seed 5000, drawing 11)
    row = _drawn_photo(tmp_path, 22.83704096829267, 193861269, lambda im: im[:, ::-1])
    assert row["status"] == "failed" or abs(row["angle_deg"] - 22.83704096829267) < 5, row


def test_a_finger_parted_from_a_wider_spread_finger_behind_is_measured(tmp_path):
    # the middle finger behind the index spreads from it towards the tips: parted, the
    # index is measured right (the cluttered benchmark suite of seed 2026, drawing 2;
    # drawing 6, spread wider, is refused as two fingers since the foreground's opening
    # was centred)
    row = _drawn_photo(tmp_path, 33.61388352028066, 930941421)
    assert row["status"] == "ok", row["reason"]
    assert abs(row["angle_deg"] - 33.61388352028066) < 1.5


@pytest.mark.parametrize("angle,rng,turn", [
    (5.061242305742143, 97842643, cv2.ROTATE_90_CLOCKWISE),
    (9.294020962468307, 1833401219, cv2.ROTATE_180),
])
def test_a_palm_ending_beyond_the_knuckle_does_not_tilt_the_hands_arm(tmp_path, angle, rng, turn):
    # a palm much thicker than the finger ends in a rounded step beyond the knuckle: the
    # hand's window took in that rounded end, its edges 19 deg apart, and the hand's arm
    # tilted: 5.9 and 5.8 deg off, sure (cluttered suite of seed 5000, drawings 67 and 92,
    # turned). The hand's window now starts where the silhouette reaches the hand's width
    row = _drawn_photo(tmp_path, angle, rng, lambda im: cv2.rotate(im, turn))
    assert row["status"] == "ok", row["reason"]
    assert abs(row["angle_deg"] - angle) < 1.0


def test_a_silhouette_that_keeps_widening_keeps_the_hands_usual_window(tmp_path):
    # the finger cut short at a tape band (its tip in the wall's colours), the hand
    # widening steadily towards the picture's edge: the "knuckle" is found on the hand,
    # and a hand's window started where the silhouette reaches the hand's width left
    # out what made it unsure: 45 deg off, sure (realistic, seed 5000, render 23, upside
    # down). Only a step up to a width the silhouette then keeps moves the window
    row = _as_saved_photo(tmp_path, 51.361735825018265, 1975632250, "realistic",
                          lambda im: cv2.rotate(im, cv2.ROTATE_180))
    assert row["status"] == "failed" or abs(row["angle_deg"] - 51.361735825018265) < 5, row


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_second_finger_overlapping_the_index_is_named_in_the_reason(seed):
    # the next finger, bent 15 deg more, lies behind the index along its whole first
    # phalanx: the silhouette's "finger" is both together (as wide as the hand, or
    # bent most where they part, like a second joint). An ROI cannot part them (the old
    # advice); curling the other fingers away can
    img, _ = render_finger(40.0, shape=(960, 1280), rng=seed, difficulty="clean", other_finger=True, palm_mm=NO_PALM)
    m = measure_angle(img)
    assert (m.status == "ok" and abs(m.angle_deg - 40.0) < 1.5) or "curl the other fingers" in m.reason, m.reason


@pytest.mark.parametrize("turn", [None, np.fliplr], ids=["as rendered", "mirrored"])
def test_two_fingers_together_are_not_taken_for_a_finger_on_a_hand_with_a_palm(turn):
    # the benchmark's hard render 41 of seed 5000 (the preset's hand, its palm 5.1 mm):
    # the middle finger behind the index, and the two together taken for the finger,
    # 1.1x as thick as the "hand" beyond their knuckle: 22.2 deg for 16.9, sure, in every
    # turn while the hand needed only be 1.1x the finger (a hand with a palm is about 2x)
    img, _ = _benchmark_photo(16.92465329853626, 1443704849, "hard", transform=turn, palm_mm=5.06765555449137)
    m = measure_angle(img)
    assert m.status == "failed" and "as wide as the hand" in m.reason, (m.angle_deg, m.reason)


def test_fingers_drawn_another_way_than_the_renderer_are_measured():
    # flexcal.synthetic.drawn shares no code, shapes or colours with the renderer the
    # method was built on: capsules with a sqrt-shaded rim, any skin tone or glove
    # colour, any background colour, any roll, either side for the palm
    rng = np.random.default_rng(40)
    errors, off_vertex = [], []
    for _ in range(12):
        a = float(rng.uniform(0, 90))
        img, truth = draw_finger(a, shape=(960, 1280), rng=int(rng.integers(2**31)))
        m = measure_angle(img)
        errors.append(m.angle_deg - a)
        if m and a > 20:    # (the arms' crossing is ill-defined for a nearly straight finger)
            off_vertex.append(np.hypot(*(np.asarray(m.vertex) - truth.vertex_xy)) / truth.params["finger_width_px"])
    errors = np.array(errors)
    answered = np.isfinite(errors)
    assert answered.sum() >= 10, errors
    assert np.abs(errors[answered]).max() < 4.0, errors
    assert np.abs(errors[answered]).mean() < 0.8, errors
    assert max(off_vertex) < 1.25, off_vertex


def test_a_silhouette_rebuilt_without_the_fingers_rims_does_not_set_the_knuckle():
    # A thin, blurred drawn finger whose shaded rims the skin-edge search takes for a
    # layer: the first silhouette is refused (its edges scatter), and the arm grown from
    # its colour over the picture is only the finger's bright core. Its width near the
    # tip is half the finger's, so the knuckle, sought 4.8-8 such widths from the tip,
    # fell on the straight finger: 1.4 deg, sure, for a bend of 53 deg
    a = 53.24424245489726
    img, _ = draw_finger(a, shape=(480, 640), rng=376903135)
    m = measure_angle(img)
    assert not m or abs(m.angle_deg - a) < 2.0, (m.angle_deg, m.reason)


@pytest.mark.parametrize("turn", [lambda im: cv2.rotate(im, cv2.ROTATE_180), lambda im: im[:, ::-1]],
                         ids=["upside down", "mirrored"])
def test_a_rebuilt_finger_that_lost_its_rims_is_measured_with_the_first_silhouettes_width(turn, found_without_a_palm):
    # held-out 40000 realistic 59: the sensor's strip along the hand's side joins the
    # first silhouette ("as wide as the hand"); the forearm's colours part it off but cut
    # off the finger's rims too, and their sure answer (75.0 deg) was dropped, as the
    # core's width could have put the knuckle on the finger. Measured with the first
    # silhouette's width, rims and all, it is sure and right
    a = 74.94892302716946
    img, _ = _benchmark_photo(a, 1574722115, "realistic", transform=turn)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - a) < 1.0, (m.angle_deg, m.reason)


def test_no_part_on_the_edge_names_the_causes_and_an_roi_measures_it(tmp_path):
    # the benchmark's realistic render 21 of seed 20000: a wood platform in the skin's
    # colours covers much of the picture's edge and the hand, so the skin's colours are the
    # background's and nothing else enters the picture. The reason says so and what to do
    # (it used to ask whether the finger was in view); an ROI around the hand and finger,
    # as it advises, measures the photo right
    from flexcal.measure import measure_file
    a = 2.5733213027490462
    path = _saved_photo(tmp_path, a, 1707220939, "realistic")
    row, _ = measure_file(path)
    assert row["status"] == "failed" and row["reason"].startswith("no elongated object"), row
    assert "share colours with the wall or a platform" in row["reason"] and "give an ROI" in row["reason"]
    row, _ = measure_file(path, roi=(300, 300, 980, 420))
    assert row["status"] == "ok" and abs(row["angle_deg"] - a) < 1.0, row


def test_too_little_hand_says_how_long_and_wide_the_part_taken_for_the_finger_is():
    # held-out 100000 hard 88: a poster and a cutting mat joined at the fingertip make the
    # "finger" a fifth of the picture wide; the reason says so, and what to do either way
    a = 26.117997276899857
    img, _ = _benchmark_photo(a, 851772258, "hard")
    m = measure_angle(img)
    assert m.status == "failed" and m.reason.startswith("too little of the hand is in the picture"), m.reason
    found = re.search(r"is ([0-9.]+) of its widths long and ([0-9]+)% of the picture's long side wide", m.reason)
    assert found and float(found.group(1)) < 8 and int(found.group(2)) >= 15, m.reason
    assert "frame the whole finger" in m.reason and "move what is joined to its tip" in m.reason


@pytest.mark.parametrize("left, right, lost", [(5, 3, True), (3, 3, True), (0, 8, False), (1, 0, False),
                                                (15, 15, False)])
def test_a_rebuilt_finger_narrower_on_both_sides_lost_its_rims(left, right, lost):
    # a horizontal finger 20 px wide on a rebuilt silhouette, and the first silhouette
    # reaching past its upper edge by `left` px and past its lower edge by `right`:
    # past both by a tenth of its width or more, the rebuilt one lost the skin's rims; an
    # object cut off on one side (0 and 8 px) or a pixel of outline is no loss, nor is an
    # object across the finger (15 px past both edges: 2.5 times its width, rims never are)
    from flexcal.vision.angle import _rims_lost
    from flexcal.vision.measurement import Arm
    first = np.zeros((200, 300), np.uint8)
    first[90 - left:110 + right, :250] = 1
    m = AngleMeasurement(distal=Arm(np.array([150.0, 100.0]), np.array([1.0, 0.0]), 40.0),
                         details=dict(finger_width_px=20.0, finger_window_width=1.0))
    wf_first = (20 + left + right) / 1.1     # the first silhouette's finger: as wide in its window as at its tip x1.1
    assert _rims_lost(first, wf_first, m, 1.0) is lost


def test_drawn_fingers_with_clutter_are_measured_or_refused_never_misread():
    # drawn with, at random, a striped background, the sensor's lead running off the
    # picture and the middle finger behind the index, bent further (the silhouette forks
    # at the knuckle, or the two fingers overlap: parted, the front finger is measured in
    # about half of them, the rest refused)
    rng = np.random.default_rng(50)
    answered = {False: [], True: []}
    for _ in range(8):
        a = float(rng.uniform(0, 90))
        img, truth = draw_finger(a, rng=int(rng.integers(2**31)), cluttered=True)
        m = measure_angle(img)
        assert not m or abs(m.angle_deg - a) < 3.0, (a, m.angle_deg, truth.params)
        answered[truth.params["other_finger"]].append(bool(m))
    plain, behind = answered[False], answered[True]
    assert len(plain) >= 3 and sum(plain) >= len(plain) - 1, plain
    assert len(behind) >= 3 and sum(behind) >= len(behind) / 2, behind


@pytest.mark.parametrize("angle, rng", [(29.57356498952379, 325430167), (38.79803920034059, 1332676692)])
def test_a_dark_rim_that_passes_for_a_layer_here_and_there_is_measured_on_the_outline(angle, rng):
    # thin, blurred drawn fingers whose rims, shaded as a cylinder's, darken over a few
    # pixels: the skin-edge search took them for a layer (a sensor strip) at some points
    # and not at others, the edge moved only there scattered, and the photo was refused
    # ("much of an arm's outline is not straight"); the outline itself runs straight
    img, _ = draw_finger(angle, shape=(480, 640), rng=rng)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - angle) < 1.5, (m.angle_deg, m.reason)


@pytest.mark.parametrize("angle, rng, why", [(51.87537705780741, 10908, "too thin"),
                                             (53.81538248073383, 20957, "turns again")])
def test_a_silhouette_narrower_than_the_finger_is_not_measured_on_the_finger(angle, rng, why):
    # realistic renders with a black glove, saved as JPEG and read as `flexcal measure`
    # reads them: a strip along the glove (its lit top) went to the background, the
    # silhouette's width near the tip was about half the finger's, and the knuckle,
    # sought so many widths from the tip, was placed on the finger itself (1.5 deg for
    # 52, 0.5 for 54, sure). Beyond the arm taken for the hand the silhouette turns by
    # the whole bend, wider; the first strip is also too thin for a finger (2.4 % of the
    # picture's long side)
    from flexcal.vision.angle import _measure_silhouette, _segment
    img, truth = _benchmark_photo(angle, rng, "realistic", glove="black")
    work, f, seg = _segment(img)
    first = _measure_silhouette(work, f, seg.mask, seg.contrast, cut_off=seg.cut_off)
    assert first.status == "failed" and why in first.reason, (first.angle_deg, first.reason)
    m = measure_angle(img)
    assert m.status != "ok" or abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)


def _midline_beyond_the_hand(pieces, widen, wf=40.0, b=200.0, end_w=12.0):
    """A midline (points, arclengths, widths) from the tip (0) along +x past the knuckle
    at ``b``; beyond the hand's window (``HAND_WIN``) it runs in the directions of
    ``pieces`` ((length in widths, deg from the hand's arm), the last kept to the end),
    ``widen`` times as wide as the hand is in its window. Returns the arguments of
    ``_turns_again`` but the window and the hand's direction."""
    from flexcal.vision.angle import HAND_WIN
    hand_end = b + HAND_WIN[1] * wf
    starts = hand_end + wf * np.cumsum([0.0] + [n for n, _ in pieces])
    s = np.arange(0.0, b + end_w * wf, 1.0)
    deg = np.zeros_like(s)
    for (_, d), lo in zip(pieces, starts):
        deg[s >= lo] = d
    step = np.column_stack([np.cos(np.radians(deg)), np.sin(np.radians(deg))])
    mid = np.cumsum(step, axis=0)
    width = np.where(s < b, wf, np.where(s > hand_end, 1.6 * wf * widen, 1.6 * wf))
    return mid, s, width, b, wf, float(s[-1])


@pytest.mark.parametrize("pieces, widen, turns", [
    ([], 1.0, False),
    # something joined along the hand: the midline turns 20 deg for 2.5 widths and runs
    # on straight, as wide as the hand (held-out 10000 realistic 76 upside down, before
    # the foreground's opening was centred: 14-24 deg, then 1)
    ([(2.5, 20.0), (10.0, 0.0)], 1.0, False),
    # the same widening: the knuckle itself beyond an arm of the finger taken for the hand
    ([(2.5, 20.0), (10.0, 0.0)], 1.3, True),
    # a turn kept from right beyond the window on, at any width: the second joint taken
    # for the knuckle (a tip frayed in the silhouette, the finger's width too small:
    # held-out 10000 hard 11, 15.3 deg for 22.2, sure, before the foreground's opening
    # was centred; its first silhouette is now right)
    ([(20.0, 20.0)], 1.0, True),
])
def test_a_turn_beyond_the_hands_arm_is_the_knuckle_unless_it_straightens_again_as_wide(pieces, widen, turns):
    from flexcal.vision.angle import HAND_WIN, _turns_again
    mid, s, width, b, wf, end = _midline_beyond_the_hand(pieces, widen)
    again = _turns_again(mid, s, width, b, wf, HAND_WIN, np.array([1.0, 0.0]), end)
    assert (again == pytest.approx(20.0, abs=0.5)) if turns else again == 0.0, again


def test_a_black_glove_passing_for_the_platform_in_shadow_is_not_measured_as_a_strip_of_it():
    # realistic render, a black glove on a black platform: the glove's colours pass for
    # the grey platform's in shadow and are left out; what is left is a strip along the
    # hand, measured 0.4 deg for 42, sure. With those colours the silhouette is the
    # glove's, and measures right: when the two disagree, neither is taken. (The strip is
    # also too thin for a finger, 2.2 % of the picture's long side: only the silhouette
    # with those colours is sure, and it is taken.)
    from flexcal.vision.angle import _measure_segmentation, _segment, _with_shadow_colours
    from flexcal.vision.segment import segment_finger
    img, truth = _benchmark_photo(42.02246140265424, 20958, "realistic", glove="black")
    work, f, seg = _segment(img)
    assert seg.shadow_left_out
    with_shadow = segment_finger(work, shadow_as_finger=True)
    assert with_shadow.shadow_is_finger and with_shadow.mask.sum() > 3 * seg.mask.sum()
    m2 = _measure_segmentation(work, f, with_shadow)
    assert m2.status == "ok" and abs(m2.angle_deg - truth.angle_deg) < 1.5, (m2.angle_deg, m2.reason)
    strip = AngleMeasurement(angle_deg=0.4, angle_unc_deg=0.6, confidence=1.0, status="ok", method="contour")
    m, refused = _with_shadow_colours(work, f, strip)
    assert refused and m.status == "failed" and "in shadow" in m.reason, (m.angle_deg, m.reason)
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)
    # a photo with no such colours has no silhouette with them
    img, _ = render_finger(40.0, shape=SHAPE, rng=2, difficulty="clean")
    work, f, seg = _segment(img)
    assert not seg.shadow_left_out and not seg.shadow_is_finger
    assert segment_finger(work, shadow_as_finger=True).mask is None


def test_a_fingertip_narrowed_by_a_notch_along_the_finger_is_measured_with_the_fingers_width():
    # a held-out realistic render (seed 40000, render 26): light skin on a light wood
    # platform, bent 63 deg. The nail and the lit rim along the finger's top fall in the
    # platform's colour cluster and leave a shallow notch over most of the finger, so the
    # width near the tip came out 28 px for 38, and the finger's window 1.6x as wide as
    # that: refused as "not a finger". Measured again with the width the window gives.
    from flexcal.vision.angle import _measure_silhouette, _segment
    img, truth = _benchmark_photo(63.27245083252769, 1670733792, "realistic")
    work, f, seg = _segment(img)
    first = _measure_silhouette(work, f, seg.mask, seg.contrast, cut_off=seg.cut_off)
    assert first.status == "failed" and "as wide near the knuckle as near its tip" in first.reason, first.reason
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)
    assert m.details["via"] == "the finger's width from its window"
    assert m.details["finger_width_px"] > 1.2 * first.details["finger_width_px"]


def test_an_oval_poster_across_the_second_joint_is_cut_off_not_taken_for_the_fingers_rims():
    # a held-out realistic render (seed 60000, render 22; found turned by 90 deg): a pink oval
    # poster across the finger at its second joint joins the silhouette, whose width near
    # the tip is then the oval's (93 px for 27). The forearm's colours cut the oval off and
    # measure the finger sure and right, but were taken for a finger that lost its rims
    # (the first silhouette past both of its edges): refused as a second joint. The first
    # silhouette there is three times as wide as the finger: an object, not rims.
    from flexcal.vision.angle import _measure_silhouette, _segment
    # (since the foreground's opening was centred, turned its first silhouette is refused
    # before its width is known; as rendered it is the oval's, 95 px)
    img, truth = _benchmark_photo(16.583306262938954, 1569388337, "realistic")
    work, f, seg = _segment(img)
    first = _measure_silhouette(work, f, seg.mask, seg.contrast, cut_off=seg.cut_off)
    assert first.status == "failed" and first.details["finger_width_px"] > 2.5 * 27, first.details
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)


def test_a_forearm_cut_short_by_a_band_near_the_picture_edge_is_bridged_to_the_finger():
    # a held-out realistic render (seed 50000, render 29): a tape band in the wall's colour
    # crosses the hand near the picture's edge, and a poster touches the stub left there:
    # no piece on the border was finger-like (too squat), so the band was never bridged
    # and the photo was refused ("no elongated object"). The largest piece on the border
    # is bridged, and the finger beyond the band joins it.
    from flexcal.vision.segment import segment_finger
    img, truth = _benchmark_photo(42.71144188667976, 436528966, "realistic")
    seg = segment_finger(img)
    assert seg.mask is not None, seg.reason
    m = measure_angle(img)
    assert m.status == "ok" and abs(m.angle_deg - truth.angle_deg) < 1.5, (m.angle_deg, m.reason)


def test_a_poster_on_the_border_bridged_to_a_cable_is_not_taken_for_a_cut_finger(monkeypatch, tmp_path):
    # a held-out realistic render (seed 20000, render 56) mirrored: a latex glove in the
    # pale wall's colours, so nothing on the border is finger-like in six colours. The
    # largest piece there, an oval poster, bridged to the sensor's cable became
    # elongated, but only 1.2x its size: no finger beyond a band. Not taken, the finer
    # colours find the glove and measure it right (k-means' next start does not find it
    # in finer colours, and the photo is now refused: that is another check's doing)
    from flexcal.vision import angle as vision_angle
    monkeypatch.setattr(vision_angle, "_confirmed_in_finer_colours", lambda *args: True)
    row = _as_saved_photo(tmp_path, 58.634056423920796, 1380508872, "realistic",
                          transform=lambda im: im[:, ::-1])
    assert row["status"] == "ok" and abs(row["angle_deg"] - 58.634056423920796) < 1.5, row


@pytest.mark.parametrize("from_stub", [True, False])
def test_an_unsure_part_bridged_from_a_stub_leaves_the_finer_colours_free_to_answer(monkeypatch, from_stub):
    # nothing on the picture's edge was finger-like in six colours, and the stub bridged
    # there measured unsure (seed 2026 hard render 60 on k-means draw 1, before the
    # foreground's opening was centred: an arm bent 43 deg inside it). It is no first
    # guess for the finer colours to agree with, as when no part was found: their sure
    # answer on a silhouette elsewhere counts. A part that was finger-like is a guess,
    # and a finer silhouette elsewhere does not count against it
    from flexcal.vision import angle
    from flexcal.vision.segment import Segmentation
    shape = (120, 160)
    first, finer = np.zeros(shape, np.uint8), np.zeros(shape, np.uint8)
    first[50:70, :40], finer[20:40, :] = 1, 1
    stub = Segmentation(first, from_stub=from_stub)
    unsure = AngleMeasurement(angle_deg=50.0, angle_unc_deg=3.0, confidence=0.3, status="low_confidence")
    sure = AngleMeasurement(angle_deg=8.0, angle_unc_deg=0.5, confidence=1.0, status="ok")
    monkeypatch.setattr(angle, "segment_finger", lambda work, k, seed: Segmentation(finer))
    monkeypatch.setattr(angle, "_measure_segmentation",
                        lambda work, f, seg, readings=None: unsure if seg is stub else sure)
    m = angle._measure_segmentations((np.zeros(shape + (3,), np.uint8), 1.0, stub), [])
    assert m.angle_deg == (8.0 if from_stub else 50.0) and m.status == ("ok" if from_stub else "low_confidence")


def _tube_midline(bump, one_sided=False, wf=40.0):
    """The midline pairs of a straight tube ``wf`` px wide (arclengths 0-400 px) with a
    stretch 20 px long, 200-220 px from the tip, ``bump`` px wider: standing off both
    sides alike (a band) or only one (something joined to it)."""
    s = np.arange(0.0, 400.0, 0.5)
    on = (s >= 200) & (s <= 220)
    width = np.where(on, wf + bump, wf)
    mid = np.column_stack([s, np.where(on & one_sided, bump / 2, 0.0)])
    return mid, s, width


def test_a_band_across_the_finger_is_found_by_its_outline():
    from flexcal.vision.angle import _bands
    wf = 40.0
    bands = _bands(*_tube_midline(0.12 * wf), wf)
    assert len(bands) == 1
    # the band and its own edges (skin_edge's margin of a quarter width on either side)
    lo, hi = bands[0]
    assert abs(lo - (200 - 0.25 * wf)) <= 1 and abs(hi - (220 + 0.25 * wf)) <= 1, (lo, hi)
    # a bump on one side only moves the midline: no band
    assert _bands(*_tube_midline(0.12 * wf, one_sided=True), wf) == []
    # nor is a slightly wider stretch (the outline's own unevenness)
    assert _bands(*_tube_midline(0.04 * wf), wf) == []


@pytest.mark.parametrize("angle,rng", [
    (51.162391328793284, 1836209556),    # benchmark --glove latex, seed 2026, render 43
    (86.46875495634715, 721837863),      # render 97
])
def test_tape_in_a_latex_gloves_colour_is_no_edge_of_the_finger(angle, rng):
    # White tape on a latex glove is nearly the glove's colour: skin_edge took it for the
    # glove, and the outline over the band, standing off both sides of the finger, left
    # most of the finger's edge points off their lines ("much of an arm's outline is not
    # straight", refused); found by its outline, the band is left out as skin_edge leaves
    # out a band in another colour
    img, truth = _benchmark_photo(angle, rng, "realistic", glove="latex")
    m = measure_angle(img)
    assert m.status == "ok", m.reason
    assert abs(m.angle_deg - truth.angle_deg) < 1.0
