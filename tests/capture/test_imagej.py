from pathlib import Path

import numpy as np
import pytest

from flexcal.capture.imagej import read_reference
from flexcal.errors import FlexcalError

FORMATS = Path(__file__).resolve().parents[3] / "shared" / "formats"
INTERIOR = [118.333, 124.371, 175.223, 159.869, 174.245, 169.160]

needs_formats = pytest.mark.skipif(not FORMATS.is_dir(), reason="../shared/formats is not beside the checkout")


@needs_formats
@pytest.mark.parametrize("name", ["imagej_angle_tool_default.csv", "imagej_angle_tool_default.txt"])
def test_imagej_default_exports_give_bend_angles(name):
    df = read_reference(FORMATS / name)
    np.testing.assert_allclose(df["angle_deg"], 180 - np.array(INTERIOR), atol=1e-9)
    assert df["image"].isna().all() and (df["source"] == "imagej_interior").all()


@needs_formats
def test_imagej_label_only_export_keeps_labels():
    df = read_reference(FORMATS / "imagej_angle_tool_label_only.csv")
    assert list(df["image"]) == ["1402.jpg"] * 3
    np.testing.assert_allclose(df["angle_deg"], 180 - np.array(INTERIOR[:3]), atol=1e-9)


@needs_formats
def test_line_tool_export_is_read_as_interior_angles_within_range():
    # The line tool's Angle is a direction (-180..180), not an angle at a vertex; it is
    # still a number in range, so it reads, and the comparison's outliers will show it.
    df = read_reference(FORMATS / "imagej_line_tool_default.csv")
    assert len(df) == 3


def test_plain_bend_csv_and_bad_files(tmp_path):
    p = tmp_path / "ref.csv"
    p.write_text("image,angle_deg\na.jpg,12.5\nb.jpg,40\n")
    df = read_reference(p)
    assert list(df["image"]) == ["a.jpg", "b.jpg"] and list(df["angle_deg"]) == [12.5, 40.0]
    with pytest.raises(FlexcalError, match="no such reference file"):
        read_reference(tmp_path / "missing.csv")
    q = tmp_path / "noangle.csv"
    q.write_text("x,y\n1,2\n")
    with pytest.raises(FlexcalError, match="no Angle"):
        read_reference(q)
    r = tmp_path / "bad.csv"
    r.write_text(" ,Angle\n1,120\n2,abc\n")
    with pytest.raises(FlexcalError, match="line 3"):
        read_reference(r)
