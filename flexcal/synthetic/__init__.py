"""Ground truth on demand: rendered finger photos and simulated sensor streams."""

from flexcal.synthetic.render import DIFFICULTIES, FingerTruth, RenderParams, render_finger, sample_params

__all__ = ["DIFFICULTIES", "FingerTruth", "RenderParams", "render_finger", "sample_params"]
