import os
import subprocess
import sys

import cv2
import pandas as pd

from flexcal.cli import SINGLE_THREADED, main
from flexcal.measure import ANGLE_COLUMNS
from flexcal.synthetic import render_finger


def test_measure_folder_with_bad_files_keeps_every_row(tmp_path, capsys):
    photos = tmp_path / "photos"
    photos.mkdir()
    for i, a in enumerate((10.0, 45.0, 80.0)):
        img, _ = render_finger(a, shape=(480, 640), rng=i, difficulty="clean")
        cv2.imwrite(str(photos / f"p{i}.jpg"), img)
    (photos / "empty.jpg").write_bytes(b"")
    (photos / "corrupt.jpg").write_bytes(b"\xff\xd8\xff\xe0 this is not really a jpeg")
    (photos / "notes.txt").write_text("trial notes")
    cv2.imwrite(str(photos / "black.png"), (0 * img))
    cv2.imwrite(str(photos / "tiny.png"), img[:1, :1])
    out = tmp_path / "angles.csv"
    assert main(["measure", str(photos), "--out", str(out), "--overlays", str(tmp_path / "ov"), "--jobs", "2"]) == 0
    df = pd.read_csv(out)
    assert list(df.columns) == ANGLE_COLUMNS
    names = [p.split("/")[-1] for p in df["image"]]
    assert names == sorted(names) and len(names) == 8       # every file has a row, in order
    by = dict(zip(names, df.itertuples()))
    for bad, why in [("empty.jpg", "empty"), ("corrupt.jpg", "corrupt"), ("notes.txt", "not an image"),
                     ("black.png", "blank"), ("tiny.png", "too small")]:
        assert by[bad].status == "failed" and why in by[bad].reason
    good = df[[n in ("p0.jpg", "p1.jpg", "p2.jpg") for n in names]]
    assert (good["status"] != "failed").all()
    assert ((good["angle_deg"] - pd.Series([10.0, 45.0, 80.0], index=good.index)).abs() < 2).all()
    assert (tmp_path / "ov" / "contact_sheet.png").exists()
    assert len(list((tmp_path / "ov").glob("*_overlay.jpg"))) == 5   # one per readable photo
    # the terminal names each photo not measured, with why, and no photo measured sure
    said = capsys.readouterr().out
    for r in df[df["status"] == "failed"].itertuples():
        assert f"  {r.image}: failed: {r.reason}\n" in said
    for r in df[df["status"] == "ok"].itertuples():
        assert r.image not in said


def test_the_photos_not_measured_are_listed_up_to_a_limit():
    from flexcal.measure import unsure_lines

    rows = [{"image": f"p{i:02d}.jpg", "status": "ok" if i % 3 == 0 else ("failed" if i % 3 == 1 else "low_confidence"),
             "reason": "" if i % 3 == 0 else f"why {i}"} for i in range(30)]
    lines = unsure_lines(pd.DataFrame(rows), "angles.csv", limit=4)
    assert lines[1:] == ["  p01.jpg: failed: why 1", "  p02.jpg: low_confidence: why 2", "  p04.jpg: failed: why 4",
                         "  p05.jpg: low_confidence: why 5", "  ... and 16 more: the status and reason columns of "
                         "angles.csv"]
    assert unsure_lines(pd.DataFrame(rows[::3]), "angles.csv") == []       # every photo measured sure


def test_a_parallel_batch_gives_the_rows_of_one_process(tmp_path):
    from flexcal.measure import measure_files

    paths = []
    for i, a in enumerate((5.0, 30.0, 55.0, 80.0, 20.0)):
        img, _ = render_finger(a, shape=(480, 640), rng=100 + i, difficulty="realistic")
        paths.append(tmp_path / f"p{i}.jpg")
        cv2.imwrite(str(paths[-1]), img)
    serial = measure_files(paths, jobs=1, progress=False)
    # answers to compare, not only refusals (the 80 deg photo at this size is refused
    # since an arm measured on its midline is never sure: 80.2 deg before)
    assert serial["angle_deg"].notna().sum() >= 3
    pd.testing.assert_frame_equal(serial, measure_files(paths, jobs=2, progress=False))


def test_the_commands_run_opencv_and_the_blas_in_one_thread_per_process(tmp_path):
    # a batch runs a process per core: a thread pool in each would only contend for them.
    # In a fresh process, as the command runs (the libraries read it when first loaded)
    img, _ = render_finger(30.0, shape=(480, 640), rng=1, difficulty="clean")
    cv2.imwrite(str(tmp_path / "p.jpg"), img)
    code = ("import os, sys; from flexcal.cli import main; assert main(sys.argv[1:]) == 0; import cv2; "
            "print(cv2.getNumThreads(), os.environ['OPENBLAS_NUM_THREADS'])")
    env = {k: v for k, v in os.environ.items() if k not in SINGLE_THREADED}
    out = subprocess.run([sys.executable, "-c", code, "measure", str(tmp_path / "p.jpg"), "--out",
                          str(tmp_path / "a.csv"), "--jobs", "1"], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.splitlines()[-1].split() == ["1", "1"], out.stdout
    assert len(pd.read_csv(tmp_path / "a.csv")) == 1


def test_measure_missing_path_is_a_one_line_error(tmp_path, capsys):
    assert main(["measure", str(tmp_path / "nope"), "--out", str(tmp_path / "a.csv")]) == 2
    err = capsys.readouterr().err.strip()
    assert "nope" in err and "no such file" in err and len(err.splitlines()) == 1


def test_measure_glob(tmp_path):
    img, _ = render_finger(30.0, shape=(480, 640), rng=1, difficulty="clean")
    for t in ("trial_01", "trial_02"):
        (tmp_path / t / "images").mkdir(parents=True)
        cv2.imwrite(str(tmp_path / t / "images" / "a.png"), img)
    out = tmp_path / "angles.csv"
    assert main(["measure", str(tmp_path / "trial_*" / "images"), "--out", str(out), "--jobs", "1"]) == 0
    assert len(pd.read_csv(out)) == 2


def test_overlay_names_stay_unique_across_trial_folders(tmp_path):
    from flexcal.measure import overlay_names, photo_labels

    assert overlay_names([tmp_path / "a.jpg", tmp_path / "b.png"]) == ["a_overlay.jpg", "b_overlay.jpg"]
    paths = [tmp_path / t / "images" / "step_01.jpg" for t in ("trial_01", "trial_02")]
    for p in paths:
        p.parent.mkdir(parents=True)
        p.touch()
    names = overlay_names(paths)
    assert names == ["trial_01__images__step_01_overlay.jpg", "trial_02__images__step_01_overlay.jpg"]
    # and the contact sheet's captions tell them apart the same way
    assert photo_labels(paths) == ["trial_01/images/step_01.jpg", "trial_02/images/step_01.jpg"]
    assert photo_labels([tmp_path / "a.jpg", tmp_path / "b.png"]) == ["a.jpg", "b.png"]


def test_a_phone_photo_stored_sideways_is_measured_as_shown(tmp_path):
    # phones store the sensor's pixels and an EXIF orientation tag (6: turn 90 deg
    # clockwise to show); the angles table's vertex and the overlay are in the photo as
    # shown, in the reduced decode of a large photo as in the full one
    import numpy as np
    from PIL import Image

    from flexcal.measure import measure_file
    img, truth = render_finger(50.0, shape=(960, 1280), rng=3, difficulty="clean")
    stored = cv2.rotate(img, cv2.ROTATE_90_COUNTERCLOCKWISE)
    exif = Image.Exif()
    exif[0x0112] = 6
    path = tmp_path / "phone.jpg"
    Image.fromarray(cv2.cvtColor(stored, cv2.COLOR_BGR2RGB)).save(path, exif=exif, quality=92)
    row, thumb = measure_file(path, overlay_dir=tmp_path)
    assert row["status"] == "ok" and abs(row["angle_deg"] - 50.0) < 1.5
    off = np.hypot(row["vertex_x"] - truth.vertex_xy[0], row["vertex_y"] - truth.vertex_xy[1])
    assert off < 30, (row["vertex_x"], row["vertex_y"], truth.vertex_xy)
    assert cv2.imread(str(tmp_path / "phone_overlay.jpg")).shape[:2] == (960, 1280)
    assert thumb.shape[1] > thumb.shape[0]           # shown landscape, as rendered


def test_a_heic_photo_gets_a_row_saying_to_export_jpeg(tmp_path):
    # an iPhone's photos are HEIC by default, which OpenCV cannot read: listed with the
    # photos (not skipped), and its row says what to do
    photos = tmp_path / "photos"
    photos.mkdir()
    img, _ = render_finger(30.0, shape=(480, 640), rng=1, difficulty="clean")
    cv2.imwrite(str(photos / "IMG_0001.JPG"), img)
    (photos / "IMG_0002.HEIC").write_bytes(b"\x00\x00\x00\x18ftypheic\x00\x00\x00\x00mif1heic" + bytes(200))
    (photos / "IMG_0003.jpg").write_bytes(b"\x00\x00\x00\x18ftypheic\x00\x00\x00\x00mif1heic" + bytes(200))
    out = tmp_path / "angles.csv"
    assert main(["measure", str(photos), "--out", str(out)]) == 0
    df = pd.read_csv(out)
    assert [p.split("/")[-1] for p in df["image"]] == ["IMG_0001.JPG", "IMG_0002.HEIC", "IMG_0003.jpg"]
    assert df["status"].tolist() == ["ok", "failed", "failed"]
    for reason in df["reason"][1:]:     # by its suffix, or by its content under another name
        assert "HEIC" in reason and "export the photos as JPEG" in reason


def test_heic_photos_are_listed_with_a_trials_photos(tmp_path):
    from flexcal.capture.images import find_images
    for name in ("a.jpg", "b.HEIC", "c.dng", "notes.txt"):
        (tmp_path / name).write_bytes(b"x")
    assert [p.name for p in find_images([tmp_path])] == ["a.jpg", "b.HEIC", "c.dng"]
