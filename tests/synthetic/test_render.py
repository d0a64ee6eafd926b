from dataclasses import fields

import numpy as np
import pytest

from flexcal.synthetic import RenderParams, render_finger, sample_params

SMALL = (360, 480)


def _direction(points):
    """Unit direction of the best line through points, oriented from first to last."""
    p = points - points.mean(axis=0)
    d = np.linalg.svd(p)[2][0]
    return d if np.dot(d, points[-1] - points[0]) > 0 else -d


def _edge_distance(mask, start, direction, limit=400):
    """Distance (px) from start along direction to the first pixel outside mask."""
    for r in np.arange(0, limit, 0.25):
        x, y = start + r * direction
        xi, yi = int(round(x)), int(round(y))
        if not (0 <= yi < mask.shape[0] and 0 <= xi < mask.shape[1]) or not mask[yi, xi]:
            return r
    return limit


@pytest.mark.parametrize("angle,roll,mirror", [(0, 0, False), (35, 20, True), (70, -30, False), (90, 160, True)])
def test_truth_arms_run_along_the_midline_of_the_drawn_finger(angle, roll, mirror):
    # (a hand without a palm: a palm thickens the hand on one side of its axis only, and
    # the hand's arm, parallel to its back and flat palm, no longer runs along its midline)
    img, truth = render_finger(angle, shape=(720, 960), rng=3, roll_deg=roll, mirror=mirror, sensor=False,
                               offset_px=(0, 0), scale=1.0, pip_deg=0.0, palm_mm=0.0)
    mask = truth.mask
    for arm in (truth.proximal_xy, truth.distal_xy):
        d = arm[-1] - arm[0]
        d /= np.linalg.norm(d)
        n = np.array([-d[1], d[0]])
        # away from the joint (where the knuckle rounds the outline), both edges are equally far
        for q in arm[3:-1]:
            assert mask[int(round(q[1])), int(round(q[0]))], "axis point outside the finger"
            a, b = _edge_distance(mask, q, n), _edge_distance(mask, q, -n)
            assert abs(a - b) <= 1.5, f"axis is {abs(a - b) / 2:.1f} px off the midline"
            assert 0.6 * 9 * truth.px_per_mm < a + b < 2.2 * 12 * truth.px_per_mm


@pytest.mark.parametrize("angle", [0.0, 12.5, 47.0, 90.0, 135.0])
def test_truth_angle_is_the_angle_between_the_arms(angle, rng):
    roll = float(rng.uniform(-180, 180))
    _, truth = render_finger(angle, shape=SMALL, rng=1, roll_deg=roll, mirror=bool(rng.random() < 0.5))
    dp = _direction(truth.proximal_xy[::-1])  # towards the vertex
    dd = _direction(truth.distal_xy)          # away from the vertex
    measured = np.degrees(np.arccos(np.clip(np.dot(dp, dd), -1, 1)))
    assert measured == pytest.approx(angle, abs=1e-6)
    np.testing.assert_allclose(truth.proximal_xy[0], truth.vertex_xy)
    np.testing.assert_allclose(truth.distal_xy[0], truth.vertex_xy)


def test_vertex_sits_inside_the_knuckle():
    for angle in (0, 45, 90):
        _, truth = render_finger(angle, shape=(720, 960), rng=2, sensor=False, roll_deg=0, scale=1.0)
        x, y = truth.vertex_xy
        assert truth.mask[int(round(y)), int(round(x))]
        # the joint centre is one knuckle radius (11 mm) below the back of the hand
        up = _edge_distance(truth.mask, truth.vertex_xy, np.array([0.0, -1.0]))
        assert up == pytest.approx(11 * truth.params.hand_size * truth.px_per_mm, rel=0.08)


def test_markers_lie_on_the_arms_and_give_the_angle():
    _, truth = render_finger(55, shape=SMALL, rng=4, markers=True)
    prox, joint, dist = truth.markers_xy
    np.testing.assert_allclose(joint, truth.vertex_xy)
    a, b = joint - prox, dist - joint
    ang = np.degrees(np.arccos(np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b)))
    assert ang == pytest.approx(55, abs=1e-6)


def test_same_seed_same_image_other_seed_other_image():
    a, ta = render_finger(30, shape=SMALL, rng=7, difficulty="realistic")
    b, tb = render_finger(30, shape=SMALL, rng=7, difficulty="realistic")
    c, _ = render_finger(30, shape=SMALL, rng=8, difficulty="realistic")
    assert np.array_equal(a, b) and ta.params == tb.params
    assert not np.array_equal(a, c)


def test_output_type_and_shape_non_square():
    img, truth = render_finger(20, shape=(301, 533), rng=0)
    assert img.dtype == np.uint8 and img.shape == (301, 533, 3)
    assert truth.mask.shape == (301, 533) and truth.mask.dtype == bool


# A value unlike the clean default for every nuisance parameter.
CHANGED = dict(
    skin_tone=0.95, glove="nitrile_blue", background="wood", background_bgr=(60, 90, 160), platform="mat",
    roll_deg=25.0, mirror=True, scale=1.3, offset_px=(40.0, -30.0), hand_size=1.1, finger_length=1.2, palm_mm=8.0, pip_deg=30.0,
    light_deg=-30.0, shadow=0.9, exposure=0.7, white_balance=(1.2, 1.0, 0.8), vignette=0.6, noise_sigma=8.0,
    blur_sigma=2.5, jpeg_quality=30, sensor=False, tape=True, cable=True, other_finger=True,
    other_finger_deg=30.0, markers=True, texture_seed=99,
)


def test_every_nuisance_parameter_is_exercised():
    assert set(CHANGED) == {f.name for f in fields(RenderParams)}, "a parameter is missing from CHANGED"
    # start from the documented defaults, so that nothing is drawn at random
    base_params = {f.name: getattr(RenderParams(), f.name) for f in fields(RenderParams)}
    base, _ = render_finger(40, shape=SMALL, rng=5, **base_params)
    for name, value in CHANGED.items():
        kw = dict(base_params, **{name: value})
        if name == "other_finger_deg":
            kw["other_finger"] = True
            ref, _ = render_finger(40, shape=SMALL, rng=5, **dict(base_params, other_finger=True))
        else:
            ref = base
        img, truth = render_finger(40, shape=SMALL, rng=5, **kw)
        diff = np.abs(img.astype(int) - ref.astype(int)).mean()
        assert diff > 0.05, f"{name}={value!r} did not change the image"
        assert getattr(truth.params, name) == value


@pytest.mark.parametrize("difficulty", ["clean", "realistic", "hard"])
def test_difficulty_presets_draw_valid_parameters(difficulty):
    rng = np.random.default_rng(0)
    for _ in range(30):
        p = sample_params(difficulty, rng)
        render_finger(45, shape=(120, 160), rng=1, **{f.name: getattr(p, f.name) for f in fields(p)})
    hard = [sample_params("hard", rng) for _ in range(50)]
    clean = [sample_params("clean", rng) for _ in range(50)]
    assert np.mean([p.noise_sigma for p in hard]) > 3 * np.mean([p.noise_sigma for p in clean])
    assert max(abs(p.roll_deg) for p in clean) <= 3


@pytest.mark.parametrize("difficulty", ["clean", "realistic", "hard"])
def test_presets_give_the_hand_a_palm(difficulty):
    # real hands are 5-10 mm thicker across the palm than the finger at the knuckle
    palms = [sample_params(difficulty, np.random.default_rng(s)).palm_mm for s in range(40)]
    assert all(5 <= p <= 10 for p in palms) and np.std(palms) > 1


@pytest.mark.parametrize("kwargs,name", [
    (dict(angle_deg=-1), "angle_deg"), (dict(angle_deg=181), "angle_deg"), (dict(angle_deg=float("nan")), "angle_deg"),
    (dict(shape=(0, 0)), "shape"), (dict(shape=()), "shape"), (dict(noise_sigma=-0.5), "noise_sigma"),
    (dict(blur_sigma=-1), "blur_sigma"), (dict(scale=0), "scale"), (dict(skin_tone=1.5), "skin_tone"),
    (dict(jpeg_quality=0), "jpeg_quality"), (dict(glove="wool"), "glove"), (dict(difficulty="easy"), "difficulty"),
    (dict(colour="red"), "colour"),
])
def test_bad_parameters_raise_value_error_naming_them(kwargs, name):
    kw = dict(angle_deg=30, shape=SMALL)
    kw.update(kwargs)
    angle = kw.pop("angle_deg")
    with pytest.raises(ValueError, match=name):
        render_finger(angle, **kw)


def test_finger_length_stretches_the_phalanges_only():
    # the fingertip moves out along the finger by the extra length of the phalanges
    # (45 + 26 + 20 mm); the knuckle and the finger's thickness stay where they were
    kw = dict(shape=(720, 960), rng=2, sensor=False, roll_deg=0.0, scale=0.7, mirror=True)   # finger points left
    _, a = render_finger(0.0, finger_length=1.0, **kw)
    _, b = render_finger(0.0, finger_length=1.2, **kw)
    np.testing.assert_allclose(a.vertex_xy, b.vertex_xy)
    tip = [np.nonzero(t.mask.any(axis=0))[0].min() for t in (a, b)]
    assert tip[0] - tip[1] == pytest.approx(0.2 * 91 * a.px_per_mm, abs=3)
    col = int(round(a.vertex_xy[0] - 30 * a.px_per_mm))    # 30 mm out along the finger
    assert a.mask[:, col].sum() == b.mask[:, col].sum()


def test_palm_mm_thickens_the_hand_below_the_knuckle_only():
    # the palm rests lower by palm_mm (and the platform with it); the back of the hand,
    # the knuckle and the finger stay where they were
    kw = dict(shape=(720, 960), rng=2, sensor=False, roll_deg=0.0, scale=0.7, mirror=True, angle_deg=30.0)
    _, a = render_finger(palm_mm=0.0, **kw)
    _, b = render_finger(palm_mm=8.0, **kw)
    np.testing.assert_allclose(a.vertex_xy, b.vertex_xy)
    col = int(round(a.vertex_xy[0] + 40 * a.px_per_mm))    # 40 mm behind the knuckle, over the palm
    rows = [np.nonzero(t.mask[:, col])[0] for t in (a, b)]
    assert rows[0].min() == rows[1].min()                    # the back of the hand
    assert rows[1].max() - rows[0].max() == pytest.approx(8 * a.px_per_mm, abs=2)
