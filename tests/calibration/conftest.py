"""A small simulated experiment on disk (tiny photos), with photo angles known from the renderer."""

import numpy as np
import pandas as pd
import pytest

from flexcal.synthetic.trial import write_experiment

ANGLE_NOISE_DEG = 0.5


def truth_angles(root, noise_deg=ANGLE_NOISE_DEG, seed=11):
    """An angles table for the experiment's photos: the true angle plus vision-like noise."""
    rng = np.random.default_rng(seed)
    rows = []
    for t in sorted(root.glob("trial_*/truth.csv")):
        tr = pd.read_csv(t)
        for _, r in tr.iterrows():
            rows.append(dict(image=str(t.parent / "images" / r.image),
                             angle_deg=r.angle_deg + rng.normal(0, noise_deg), angle_unc_deg=noise_deg,
                             status="ok", reason=""))
    return pd.DataFrame(rows)


@pytest.fixture(scope="session")
def experiment(tmp_path_factory):
    """5 trials at 0:90:10 with the reference's sensor, photos 160x120, plus pressure.csv and angles.csv."""
    root = tmp_path_factory.mktemp("experiment")
    write_experiment(root, trials=5, shape=(120, 160), seed=2026, show_progress=False)
    truth_angles(root).to_csv(root / "angles.csv", index=False)
    return root
