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
