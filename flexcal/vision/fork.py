"""The branches of a silhouette, and where to seed the parting of one that forks.

A hand and finger is one tube with one free end, the fingertip. Another finger behind
the measured one (the middle finger behind the index, bent further or less) joins the
silhouette at the knuckle, and the silhouette forks: two fingers and the hand. Each
finger is seeded along its own length, the hand where it leaves the picture, and the
silhouette is parted at the strongest colour edges between them
(``segment.split_at_inner_edge``): where the finger in front is kept with the hand, its
own edge parts it from the finger behind. From the outline alone either finger could be
the one in front; ``angle._measure_split`` measures both partings and decides.
"""

from __future__ import annotations

import cv2
import numpy as np
from skimage.morphology import skeletonize

from flexcal.vision.segment import border_pixels, box, outer_outline

FORK_WIDTHS = 1.5        # a free branch of the silhouette longer than this many finger widths is a limb
FINGER_SEED_W = (1.0, 2.5)  # each finger of a fork is seeded along its outline this far from its tip (widths)
HAND_SEED_W = 1.5        # ... and the hand along its outline this far from where it leaves the picture


def free_branch_ends(mask, width_px) -> list[np.ndarray]:
    """The free ends (x, y; not at the picture's edge) of the branches of the
    silhouette's skeleton longer than ``FORK_WIDTHS`` finger widths (``width_px``,
    working pixels).

    A hand and finger is one tube with one free end, the fingertip; a second long free
    branch is something else joined to it (another finger, an object, a cable).
    """
    q = 2
    small = cv2.resize(mask, (mask.shape[1] // q, mask.shape[0] // q), interpolation=cv2.INTER_AREA) > 0
    b = box(small)
    on_edge = border_pixels(small.shape)[b]
    small = small[b]
    sk = skeletonize(small).astype(np.uint8)
    nb = cv2.filter2D(sk, -1, np.ones((3, 3), np.float32), borderType=cv2.BORDER_CONSTANT) - sk
    ends = (sk > 0) & (nb == 1)
    # the skeleton of an arm cut by the frame stops about half its width short of it:
    # an end near silhouette pixels on the picture's edge is where the arm leaves it
    cut = small & on_edge
    m = max(3, int(round(1.5 * width_px / q)))
    ends &= cv2.dilate(cut.astype(np.uint8), np.ones((2 * m + 1, 2 * m + 1), np.uint8)) == 0
    # branches: the skeleton with its junctions (and their neighbours) taken out
    junctions = cv2.dilate(((sk > 0) & (nb >= 3)).astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    n, comp = cv2.connectedComponents(((sk > 0) & ~junctions).astype(np.uint8), connectivity=8)
    length = np.bincount(comp.ravel(), minlength=n) * q
    ys, xs = np.nonzero(ends)
    ids = comp[ys, xs]
    long = (ids > 0) & (length[ids] > FORK_WIDTHS * width_px)
    return [np.array([(x + b[1].start) * q + (q - 1) / 2, (y + b[0].start) * q + (q - 1) / 2])
            for x, y in zip(xs[long], ys[long])]


def fork_seeds(mask, width_px, ends) -> tuple[list[np.ndarray], np.ndarray] | None:
    """Seeds for parting a silhouette (``mask``, its finger ``width_px`` wide) that forks
    into two fingers and the hand: (per finger, its outline points ``FINGER_SEED_W``
    widths from its tip along either side; the hand's outline points within
    ``HAND_SEED_W`` widths of where it leaves the picture), or None unless exactly two
    long branches end freely (``ends``: ``free_branch_ends`` of the silhouette)."""
    if len(ends) != 2:
        return None
    pts = outer_outline(mask)
    on_edge = border_pixels(mask.shape)[pts[:, 1].astype(int), pts[:, 0].astype(int)]
    if not on_edge.any():
        return None
    step = np.linalg.norm(pts - np.roll(pts, -1, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(step)[:-1]])
    total = step.sum()

    def along(i):     # arclength along the closed outline to the point i, the shorter way
        d = np.abs(arc - arc[i])
        return np.minimum(d, total - d)

    fingers = []
    for end in ends:
        d = along(int(np.argmin(np.linalg.norm(pts - end, axis=1))))
        fingers.append(pts[(d >= FINGER_SEED_W[0] * width_px) & (d <= FINGER_SEED_W[1] * width_px)])
    # (the nearest point on the picture's edge, along the outline, ends a run of them)
    run_ends = np.flatnonzero(on_edge & ~(np.roll(on_edge, 1) & np.roll(on_edge, -1)))
    to_edge = np.min([along(i) for i in run_ends], axis=0)
    hand = pts[~on_edge & (to_edge <= HAND_SEED_W * width_px)]
    return fingers, hand
