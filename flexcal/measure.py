"""Batch measurement of photos: the library side of ``flexcal measure``.

Reads files (``capture.images``), measures each with ``vision.measure_angle`` in
parallel processes, and returns the angles table of DESIGN.md, one row per file in
sorted order, failures included as rows with a reason.
"""

from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
from PIL import Image
from tqdm import tqdm

from flexcal.capture.images import read_image
from flexcal.vision.angle import WORK_SIZE, measure_angle
from flexcal.vision.measurement import AngleMeasurement, failed
from flexcal.vision.overlay import contact_sheet, draw_overlay

ANGLE_COLUMNS = ["image", "angle_deg", "angle_unc_deg", "confidence", "status", "reason", "method",
                 "vertex_x", "vertex_y"]


def _reduction(path: Path) -> int:
    """JPEG decode reduction that still leaves at least the working resolution."""
    if path.suffix.lower() not in (".jpg", ".jpeg"):
        return 1
    try:
        with Image.open(path) as im:      # reads the header only
            long_side = max(im.size)
    except (OSError, ValueError):         # not a readable JPEG: read_image will say why
        return 1
    for r in (4, 2):
        if long_side / r >= WORK_SIZE:
            return r
    return 1


def photo_labels(paths) -> list[str]:
    """Names that tell a batch's photos apart, for captions: each file's name or, when
    stems repeat (``trial_01/images/step_01.jpg`` and ``trial_02/images/step_01.jpg``),
    its path below the folder they all share (``trial_01/images/step_01.jpg``)."""
    paths = [Path(p) for p in paths]
    if len({p.stem for p in paths}) == len(paths):
        return [p.name for p in paths]
    absolute = [p.resolve() for p in paths]
    common = Path(os.path.commonpath([str(a.parent) for a in absolute]))
    return [a.relative_to(common).as_posix() for a in absolute]


def overlay_names(paths) -> list[str]:
    """File names for the photos' overlays, unique within a batch.

    ``<stem>_overlay.jpg``; when stems repeat (``trial_01/images/step_01.jpg`` and
    ``trial_02/images/step_01.jpg``) the folders that tell them apart are prefixed:
    ``trial_01__images__step_01_overlay.jpg`` (``photo_labels``).
    """
    return ["__".join(Path(lab).with_suffix("").parts) + "_overlay.jpg" for lab in photo_labels(paths)]


def measure_photo(path, *, roi=None, method="auto"):
    """Read one photo and measure it, never raising for what the file holds: (the
    ``AngleMeasurement``, its vertex, arms and a refusal's outline in the photo's pixels;
    the image as read, None when unreadable; the JPEG decode reduction it was read at).

    A JPEG is decoded reduced when it stays at least the working resolution
    (``_reduction``): ``measure_angle`` would shrink it to that anyway. The measurement's
    ``details`` are as ``measure_angle`` gives them, in the pixels of the image as read.
    """
    path = Path(path)
    red = 1 if roi is not None else _reduction(path)
    img, why = read_image(path, reduce=red)
    if img is None:
        return failed(why, method), None, red
    try:
        m = measure_angle(img, roi=roi, method=method)
    except ValueError as e:  # an ROI that does not fit this photo
        m = failed(str(e), method)
    except Exception as e:  # a bug must not take the batch down; the row says what happened
        m = failed(f"internal error: {type(e).__name__}: {e}", method)
    if red > 1:
        m = _scale(m, red)
    return m, img, red


def measure_file(path, *, roi=None, method="auto", overlay_dir=None, overlay_name=None, thumb_w=320):
    """Measure one photo. Returns (row dict, overlay thumbnail BGR or None).

    With ``overlay_dir`` the overlay is written there (as ``overlay_name``, by default
    ``<stem>_overlay.jpg``) and its thumbnail returned.
    """
    path = Path(path)
    m, img, red = measure_photo(path, roi=roi, method=method)
    thumb = None
    if img is not None and overlay_dir is not None:  # overlays cost a full-size decode: only when asked
        full = img if red == 1 else cv2.imread(str(path), cv2.IMREAD_COLOR)
        ov = draw_overlay(full, m)
        name = overlay_name or f"{path.stem}_overlay.jpg"
        cv2.imwrite(str(Path(overlay_dir) / name), ov, [cv2.IMWRITE_JPEG_QUALITY, 85])
        th = int(round(ov.shape[0] * thumb_w / ov.shape[1]))
        thumb = cv2.resize(ov, (thumb_w, max(1, th)), interpolation=cv2.INTER_AREA)
    row = {"image": str(path), **m.row()}
    return row, thumb


def unsure_lines(angles: pd.DataFrame, table, limit: int = 10) -> list[str]:
    """Lines for the terminal after a batch: each photo not measured (failed) or measured
    with a doubt (low_confidence), with the reason, which names what to change; the
    first ``limit`` of them in the table's order, then how many more ``table`` (the
    angles table's path) holds. No lines when every photo was measured sure."""
    rows = angles[angles["status"] != "ok"]
    if rows.empty:
        return []
    lines = ["not measured, or measured with a doubt:"]
    lines += [f"  {r.image}: {r.status}: {r.reason}" for r in rows.head(limit).itertuples()]
    if len(rows) > limit:
        lines.append(f"  ... and {len(rows) - limit} more: the status and reason columns of {table}")
    return lines


def _scale(m: AngleMeasurement, f: float) -> AngleMeasurement:
    m.vertex = (m.vertex[0] * f, m.vertex[1] * f)
    for arm in (m.proximal, m.distal):
        if arm is not None:
            arm.point = arm.point * f
            arm.length_px *= f
    if m.outline is not None:
        m.outline = m.outline * f
    return m


def _job(args):
    path, roi, method, overlay_dir, name = args
    return measure_file(path, roi=roi, method=method, overlay_dir=overlay_dir, overlay_name=name)


def measure_files(paths, *, roi=None, method="auto", jobs=None, overlay_dir=None, progress=True) -> pd.DataFrame:
    """Measure many photos in parallel; the angles table (DESIGN.md), rows in input order.

    With ``overlay_dir`` an overlay per photo and ``contact_sheet.png`` are written there.
    """
    paths = [Path(p) for p in paths]
    if overlay_dir is not None:
        Path(overlay_dir).mkdir(parents=True, exist_ok=True)
    jobs = max(1, int(jobs or os.cpu_count() or 1))
    names = overlay_names(paths) if paths else []
    tasks = [(p, roi, method, None if overlay_dir is None else str(overlay_dir), n) for p, n in zip(paths, names)]
    results = []
    with tqdm(total=len(tasks), desc="measuring", unit="photo", disable=not progress) as bar:
        if jobs == 1 or len(tasks) < 4:
            for t in tasks:
                results.append(_job(t))
                bar.update(1)
        else:
            with ProcessPoolExecutor(max_workers=jobs) as ex:
                for r in ex.map(_job, tasks, chunksize=2):
                    results.append(r)
                    bar.update(1)
    df = pd.DataFrame([r for r, _ in results], columns=ANGLE_COLUMNS)
    if overlay_dir is not None and results:
        thumbs = [(t, f"{lab}: " + (f"{r['angle_deg']:.1f} deg" if np.isfinite(r["angle_deg"]) else r["reason"]),
                   r["status"]) for (r, t), lab in zip(results, photo_labels(paths)) if t is not None]
        if thumbs:
            sheet = contact_sheet([t for t, _, _ in thumbs], [lab for _, lab, _ in thumbs],
                                  [s for _, _, s in thumbs])
            cv2.imwrite(str(Path(overlay_dir) / "contact_sheet.png"), sheet)
    return df
