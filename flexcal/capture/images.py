"""Finding and reading photos on disk. Failures are values: (None, reason)."""

from __future__ import annotations

import glob
from pathlib import Path

import cv2
import numpy as np

from flexcal.errors import FlexcalError

IMAGE_SUFFIXES = {".jpg", ".jpeg", ".png", ".tif", ".tiff", ".bmp", ".webp"}   # what OpenCV reads
# photo formats that cameras and phones write and OpenCV does not read
_UNREADABLE_KINDS = {
    ".heic": "a HEIC photo (an iPhone's default: Settings > Camera > Formats > Most Compatible takes JPEGs)",
    ".heif": "a HEIF photo", ".avif": "an AVIF photo",
    **{s: "a camera RAW file" for s in (".dng", ".cr2", ".cr3", ".nef", ".arw", ".orf", ".rw2", ".raf")},
}
PHOTO_SUFFIXES = IMAGE_SUFFIXES | set(_UNREADABLE_KINDS)   # listed as photos: an unreadable one gets a row saying why


def find_images(paths, *, all_files: bool = False) -> list[Path]:
    """Expand files, folders and glob patterns into a sorted, de-duplicated list.

    Folders contribute their photos (by suffix, ``PHOTO_SUFFIXES``: a HEIC or RAW photo
    is listed, and its row says it cannot be read; with ``all_files`` every file, so
    that a non-image in an image folder is reported rather than skipped). A path that
    matches nothing raises ``FlexcalError`` naming it.
    """
    found: list[Path] = []
    for p in paths:
        p = str(p)
        matches = [Path(m) for m in sorted(glob.glob(p))] if glob.has_magic(p) else [Path(p)]
        if not matches or not all(m.exists() for m in matches):
            raise FlexcalError(f"{p}: no such file or folder; check the path (globs need quotes in some shells)")
        for m in matches:
            if m.is_dir():
                found += [f for f in sorted(m.iterdir())
                          if f.is_file() and not f.name.startswith(".")
                          and (all_files or f.suffix.lower() in PHOTO_SUFFIXES)]
            else:
                found.append(m)
    seen, out = set(), []
    for f in found:
        key = f.resolve()
        if key not in seen:
            seen.add(key)
            out.append(f)
    return sorted(out, key=lambda f: (str(f.parent), f.name))


def photo_folder(folder) -> Path:
    """Where a trial folder keeps its photos: ``images/`` when it has one, else the folder itself."""
    folder = Path(folder)
    return folder / "images" if (folder / "images").is_dir() else folder


def read_image(path, *, reduce: int = 1):
    """Read a photo as BGR uint8 (16-bit kept as uint16). Returns (image, '') or (None, reason).

    ``reduce`` 2, 4 or 8 decodes a JPEG at that fraction of its size (much faster);
    the caller then scales coordinates back.
    """
    path = Path(path)
    try:
        data = np.fromfile(path, dtype=np.uint8)
    except OSError as e:
        return None, f"cannot read the file ({e.strerror})"
    if data.size == 0:
        return None, "the file is empty"
    flags = cv2.IMREAD_COLOR
    if reduce in (2, 4, 8) and path.suffix.lower() in (".jpg", ".jpeg"):
        flags = {2: cv2.IMREAD_REDUCED_COLOR_2, 4: cv2.IMREAD_REDUCED_COLOR_4, 8: cv2.IMREAD_REDUCED_COLOR_8}[reduce]
    elif path.suffix.lower() in (".png", ".tif", ".tiff"):
        flags = cv2.IMREAD_ANYDEPTH | cv2.IMREAD_ANYCOLOR
    img = cv2.imdecode(data, flags)
    if img is None:
        kind = _UNREADABLE_KINDS.get(path.suffix.lower())
        if kind is None and data[4:12].tobytes() in (b"ftypheic", b"ftypheix", b"ftypmif1", b"ftyphevc"):
            kind = _UNREADABLE_KINDS[".heic"]
        if kind is not None:
            return None, f"{kind} cannot be read; export the photos as JPEG (or TIFF) and measure those"
        return None, "not an image, or the image is corrupt (OpenCV could not decode it)"
    return img, ""


def exif_time_s(path) -> float | None:
    """When the camera took the photo, from EXIF DateTimeOriginal (+ SubSecTimeOriginal).

    Seconds since 1970 reading the camera's local time as if it were UTC: only the
    differences between photos are meaningful. None when the file has no such tag.
    """
    from datetime import datetime, timezone

    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as im:
            exif = im.getexif()
    except (OSError, UnidentifiedImageError):
        return None
    sub = exif.get_ifd(0x8769)   # the Exif sub-IFD holds DateTimeOriginal and its sub-seconds
    stamp = sub.get(0x9003) or exif.get(0x0132)   # DateTimeOriginal, else DateTime
    if not stamp:
        return None
    try:
        t = datetime.strptime(str(stamp).strip("\x00 "), "%Y:%m:%d %H:%M:%S").replace(tzinfo=timezone.utc).timestamp()
    except ValueError:
        return None
    frac = str(sub.get(0x9291, "")).strip("\x00 ")   # SubSecTimeOriginal
    return t + (float("0." + frac) if frac.isdigit() else 0.0)
