import numpy as np

from flexcal.synthetic import draw_finger


def test_same_seed_same_drawing_other_seed_other_drawing():
    a, ta = draw_finger(30.0, shape=(240, 320), rng=5)
    b, tb = draw_finger(30.0, shape=(240, 320), rng=5)
    c, _ = draw_finger(30.0, shape=(240, 320), rng=6)
    assert a.shape == (240, 320, 3) and a.dtype == np.uint8
    assert np.array_equal(a, b) and ta.as_dict() == tb.as_dict()
    assert not np.array_equal(a, c)


def test_the_hand_runs_from_the_knuckle_off_the_picture():
    # the skin's colour at the knuckle is found again on the picture's edge: the hand
    for seed in range(6):
        img, truth = draw_finger(45.0, shape=(480, 640), rng=seed)
        x, y = np.round(truth.vertex_xy).astype(int)
        assert 0 <= x < 640 and 0 <= y < 480
        knuckle = img[y, x].astype(float)
        border = np.concatenate([img[0], img[-1], img[:, 0], img[:, -1]]).astype(float)
        assert (np.linalg.norm(border - knuckle, axis=1) < 25).any(), seed


def test_clutter_is_drawn_over_the_same_finger():
    # the clutter has its own random stream: the finger, its bend and knuckle, and every
    # other draw are those of the plain drawing of the same seed
    clutter = ("stripes", "other_finger", "lead")
    drawn = []
    for seed in range(4):
        _, tp = draw_finger(30.0, shape=(240, 320), rng=seed)
        _, tb = draw_finger(30.0, shape=(240, 320), rng=seed, cluttered=True)
        assert np.array_equal(tp.vertex_xy, tb.vertex_xy)
        assert {k: v for k, v in tb.params.items() if k not in clutter} == \
            {k: v for k, v in tp.params.items() if k not in clutter}
        assert not any(tp.params[k] for k in clutter)
        drawn += [tb.params[k] for k in clutter]
    assert any(drawn)
