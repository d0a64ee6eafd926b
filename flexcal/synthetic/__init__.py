"""Ground truth on demand: rendered finger photos and simulated sensor streams."""

from flexcal.synthetic.drawn import DrawnTruth, draw_finger
from flexcal.synthetic.render import DIFFICULTIES, FingerTruth, RenderParams, render_finger, sample_params

__all__ = ["DIFFICULTIES", "DrawnTruth", "FingerTruth", "RenderParams", "draw_finger", "render_finger",
           "sample_params"]
