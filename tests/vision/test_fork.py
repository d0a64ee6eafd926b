"""A silhouette that forks at the knuckle: another finger behind the measured one."""

import cv2
import numpy as np
import pytest

from flexcal.capture.images import read_image
from flexcal.measure import _reduction, measure_file
from flexcal.synthetic import draw_finger, render_finger
from flexcal.vision import measure_angle
from flexcal.vision.angle import _measure_silhouette, _segment
from flexcal.vision.fork import FINGER_SEED_W, HAND_SEED_W, fork_seeds, free_branch_ends
from flexcal.vision.segment import split_at_inner_edge


def _forked(angle, rng):
    """A drawn index finger with the middle finger behind it, bent further (seeded)."""
    img, truth = draw_finger(angle, rng=rng, cluttered=True)
    assert truth.params["other_finger"]
    return img, truth


def test_the_finger_in_front_of_a_fork_is_measured_not_the_one_behind():
    # the middle finger behind the index, 8-35 deg more bent, forks the silhouette at the
    # knuckle; kept with the hand, the finger behind would give its own, larger bend
    img, _ = _forked(70.86599398862706, 1534524555)
    work, f, seg = _segment(img)
    assert "forks" in _measure_silhouette(work, f, seg.mask, seg.contrast).reason
    m = measure_angle(img)
    assert m.status == "ok" and m.details["via"] == "parted from another finger", m.reason
    assert abs(m.angle_deg - 70.86599398862706) <= 2 * m.angle_unc_deg, (m.angle_deg, m.angle_unc_deg)
    assert m.angle_unc_deg >= 2.0      # the parting's own uncertainty is in it


def test_fork_seeds_lie_along_each_finger_and_where_the_hand_leaves_the_picture():
    img, _ = _forked(23.937400376452373, 1478185405)
    work, f, seg = _segment(img)
    m = _measure_silhouette(work, f, seg.mask, seg.contrast)
    width = m.details["finger_width_px"] * f
    ends = free_branch_ends(seg.mask, width)
    assert len(ends) == 2
    assert np.array_equal(m.details["fork_ends"], ends)     # the measurement hands them on
    fingers, hand = fork_seeds(seg.mask, width, ends)
    for end, seeds in zip(ends, fingers):
        d = np.linalg.norm(seeds - end, axis=1)
        # (straight-line distances from the skeleton's end, up to the arclength along the outline)
        assert len(seeds) and d.max() <= FINGER_SEED_W[1] * width + 2 and np.median(d) >= 0.5 * width
    h, w = seg.mask.shape
    to_frame = np.minimum.reduce([hand[:, 0], hand[:, 1], w - 1 - hand[:, 0], h - 1 - hand[:, 1]])
    assert len(hand) and to_frame.max() <= HAND_SEED_W * width + 1


@pytest.mark.parametrize("difficulty", ["clean", "realistic"])
def test_a_single_finger_has_one_free_branch_and_no_fork_seeds(difficulty):
    img, _ = render_finger(40.0, rng=3, difficulty=difficulty)
    work, f, seg = _segment(img)
    m = _measure_silhouette(work, f, seg.mask, seg.contrast)
    width = m.details["finger_width_px"] * f
    ends = free_branch_ends(seg.mask, width)
    assert len(ends) == 1 and "fork_ends" not in m.details
    assert fork_seeds(seg.mask, width, ends) is None


def test_a_fork_with_a_cable_across_the_knuckle_is_refused_not_measured_on_the_finger_behind():
    # the sensor's lead crosses the knuckle: the only parting that keeps its finger joined
    # to the hand cuts the index off along the lead, and keeps the finger behind, cleanly
    # and sure (59 deg for 33); the index removed lies outside that bend: not taken
    angle = 32.686859904913575
    img, truth = _forked(angle, 2110989402)
    assert truth.params["lead"]
    for turn in (lambda im: im, lambda im: np.ascontiguousarray(np.rot90(im))):
        m = measure_angle(turn(img))
        assert not m or abs(m.angle_deg - angle) < 3.0, (m.angle_deg, m.confidence)


def test_the_finger_behind_kept_with_the_hand_is_not_taken_when_the_front_one_lies_outside_its_bend(tmp_path):
    # saved as JPEG and read as `flexcal measure` reads it: parted one way, the front
    # finger (15 deg) is cut off at its base and the finger behind, curled further, kept
    # with the hand measures sure (37 deg); the front finger removed lies outside that
    # bend, so the parting is not taken (the other one, with the front finger, is unsure)
    angle = 15.053185812944434
    img, _ = _forked(angle, 1021917955)
    path = tmp_path / "fork.jpg"
    cv2.imwrite(str(path), img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    row, _ = measure_file(path)
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 3.0, row


def test_a_fork_parted_only_one_way_is_measured_when_that_way_keeps_the_front_finger(tmp_path):
    # the lead across the knuckle again, here cutting the finger behind off: the one
    # parting that keeps its finger joined to the hand keeps the front one, and it is
    # taken (the finger behind lies within its bend). Read as `flexcal measure` reads it.
    angle = 40.033889847729355
    img, truth = _forked(angle, 1287901941)
    assert truth.params["lead"]
    path = tmp_path / "fork.jpg"
    cv2.imwrite(str(path), img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    work, f, seg = _segment(read_image(path, reduce=_reduction(path))[0])
    m = _measure_silhouette(work, f, seg.mask, seg.contrast)
    width = m.details["finger_width_px"] * f
    assert len(split_at_inner_edge(work, seg.mask, *fork_seeds(seg.mask, width, m.details["fork_ends"]),
                                   0.2 * width)) == 1
    row, _ = measure_file(path)
    assert row["status"] == "ok", row["reason"]
    assert abs(row["angle_deg"] - angle) <= 2 * row["angle_unc_deg"], (row["angle_deg"], row["angle_unc_deg"])


@pytest.mark.parametrize("angle, rng, draw", [(82.19496089569289, 1825883272, True),
                                               (38.636964268111015, 528311974, False)])
def test_a_small_piece_parted_off_is_not_taken_for_an_overlapping_finger(tmp_path, angle, rng, draw):
    # held-out cluttered drawing 110000/74: the finger behind in other colours, the
    # silhouette is the index and the hand alone, and parted as two overlapping fingers
    # it lost a sliver off the index's side, half a finger width thick and 1.6 widths
    # squared; the index, narrowed with it, set the widths and put the knuckle on the
    # finger itself: 4.5 deg for 82, sure. Hard render 20000/25 turned by 270 deg: a piece
    # as small parted off, 58 deg for 39, sure. Beside an overlapping finger what is
    # parted off shows along it (parted answers: 2.2 widths squared and more). Read as
    # `flexcal measure` reads them.
    if draw:
        img, _ = draw_finger(angle, shape=(960, 1280), rng=rng, cluttered=True)
    else:
        img, _ = render_finger(angle, shape=(960, 1280), rng=rng, difficulty="hard", jpeg_quality=None)
        img = cv2.rotate(img, cv2.ROTATE_90_COUNTERCLOCKWISE)
    path = tmp_path / "parted.jpg"
    cv2.imwrite(str(path), img, [cv2.IMWRITE_JPEG_QUALITY, 90])
    row, _ = measure_file(path)
    assert row["status"] == "failed" or abs(row["angle_deg"] - angle) < 3.0, row
