"""What a bend-angle measurement holds, and what an image must be to be measured."""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np


@dataclass
class Arm:
    """A fitted arm: a point on its axis and the unit direction pointing away from the vertex."""

    point: np.ndarray
    direction: np.ndarray
    length_px: float

    def segment(self, vertex):
        return np.asarray(vertex), np.asarray(vertex) + self.direction * self.length_px


@dataclass
class AngleMeasurement:
    """Result of ``measure_angle``. Coordinates in pixels of the input image."""

    angle_deg: float = float("nan")
    angle_unc_deg: float = float("nan")
    confidence: float = 0.0
    status: str = "failed"
    reason: str = ""
    method: str = ""
    vertex: tuple = (float("nan"), float("nan"))
    proximal: Arm | None = None
    distal: Arm | None = None
    # the method's own figures (finger width, knuckle place, taper, ...) and, for an answer
    # not from the photo's first silhouette, how its silhouette was found ("via")
    details: dict = field(default_factory=dict)
    # a refusal's silhouette: the outline (N, 2: x, y) of what was taken for the hand and
    # finger, for the overlay to show what went wrong; None when there was none
    outline: np.ndarray | None = None

    def __bool__(self):
        return self.status != "failed"

    def row(self) -> dict:
        """The angles-table fields (DESIGN.md) of this measurement."""
        return dict(angle_deg=self.angle_deg, angle_unc_deg=self.angle_unc_deg, confidence=self.confidence,
                    status=self.status, reason=self.reason, method=self.method,
                    vertex_x=self.vertex[0], vertex_y=self.vertex[1])


def failed(reason: str, method: str = "") -> AngleMeasurement:
    return AngleMeasurement(reason=reason, method=method)


def is_grey(bgr: np.ndarray, spread: int = 4) -> bool:
    """Whether a BGR uint8 picture has no colour: its channels differ by more than
    ``spread`` levels at no more than 1 % of its pixels (every 8th row and column). A
    grey photo, whatever file it came in, differs by 0-1 levels; of the benchmark's
    colour renders and drawings at least 15 % of the pixels differ by more, and a black
    glove on a grey wall and platform 11 % (the light's colour, the white balance)."""
    sample = bgr[::8, ::8]
    coloured = np.count_nonzero(sample.max(axis=2) - sample.min(axis=2) > spread)
    return coloured <= 0.01 * sample.shape[0] * sample.shape[1]


def as_bgr8(image) -> np.ndarray:
    """Any 2-D grey or 3/4-channel image, uint8 / uint16 / float, as BGR uint8."""
    img = np.asarray(image)
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] not in (1, 3, 4)):
        raise ValueError(f"image must be a (H, W) grey or (H, W, 3|4) colour array, got shape {img.shape}")
    if img.dtype == np.uint16:
        img = (img / 257.0 + 0.5).astype(np.uint8)
    elif img.dtype.kind == "f":
        top = 1.0 if np.nanmax(img) <= 1.0 else 255.0
        img = np.clip(np.nan_to_num(img) / top * 255 + 0.5, 0, 255).astype(np.uint8)
    elif img.dtype == bool:
        img = img.astype(np.uint8) * 255
    elif img.dtype != np.uint8:
        raise ValueError(f"image dtype must be uint8, uint16, float or bool, got {img.dtype}")
    if img.ndim == 2 or img.shape[2] == 1:
        img = cv2.cvtColor(img.reshape(img.shape[:2]), cv2.COLOR_GRAY2BGR)
    elif img.shape[2] == 4:
        img = cv2.cvtColor(img, cv2.COLOR_BGRA2BGR)
    return np.ascontiguousarray(img)
