import hashlib
from pathlib import Path

import pytest

from flexcal.synthetic.trial import write_experiment

SAMPLE = Path(__file__).resolve().parents[2] / "datasets" / "sample"


def _digest(root):
    return {str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(root.rglob("*")) if p.is_file() and p.name != "README.md"}


@pytest.mark.slow
def test_shipped_sample_regenerates_bit_for_bit(tmp_path):
    """The command in datasets/sample/README.md reproduces the shipped files exactly."""
    write_experiment(tmp_path, trials=5, angles_deg=range(0, 91, 10), difficulty="realistic", seed=2026,
                     shape=(960, 1280), jpeg_quality=85, show_progress=False)
    assert _digest(tmp_path) == _digest(SAMPLE)
