"""Batch re-measurement of old trials, and agreement with a hand-measured reference.

The library side of ``flexcal remeasure``: measure every photo of the trials (parallel,
overlays), map the reference's rows (ImageJ Results or image,angle_deg) to the photos,
and compare: per-photo differences, Bland-Altman bias and limits of agreement, and the
photos that disagree most.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from flexcal.capture.images import PHOTO_SUFFIXES, find_images, photo_folder
from flexcal.errors import FlexcalError

COMPARISON_COLUMNS = ["image", "angle_deg", "angle_unc_deg", "status", "reason", "reference_deg",
                      "reference_sd_deg", "reference_n", "difference_deg", "mean_deg", "overlay"]


def trial_images(dirs) -> list[Path]:
    """The photos of trial folders (in ``images/`` or the folder itself), sorted per folder."""
    out: list[Path] = []
    for d in dirs:
        d = Path(d)
        if not d.is_dir():
            raise FlexcalError(f"{d}: not a folder; give trial folders (holding images/ or photos)")
        found = find_images([photo_folder(d)])
        if not found:
            raise FlexcalError(f"{d}: no photos in it (.jpg, .png, .tif ...)")
        out += found
    return out


def _label_key(label: str) -> str:
    # ImageJ labels may carry a stack or ROI suffix: "1402.jpg:0001-0234" or "stack:1402.jpg"
    parts = [p for p in str(label).split(":") if Path(p).suffix.lower() in PHOTO_SUFFIXES]
    return Path(parts[0] if parts else str(label)).name.lower()


def map_reference(ref: pd.DataFrame, images: list[Path], source: str) -> tuple[pd.DataFrame, str]:
    """One reference angle per photo: ``image, reference_deg, reference_sd_deg, reference_n``.

    By Label when the table has one (repeated measurements of a photo are averaged);
    otherwise in sorted photo order, which needs as many rows as photos (or an exact
    multiple: then that many consecutive rows per photo, as when each photo was measured
    several times). Returns the table and a sentence saying how rows were mapped.
    """
    names = [p.name.lower() for p in images]
    stems = {p.stem.lower(): p.name.lower() for p in images}
    if ref["image"].notna().all() and ref["image"] is not None and len(ref):
        dup = {n for n in names if names.count(n) > 1}
        keys = [_label_key(lab) for lab in ref["image"]]
        keys = [k if k in names else stems.get(Path(k).stem, stems.get(k, k)) for k in keys]
        unknown = sorted({k for k in keys if k not in names})
        if unknown:
            raise FlexcalError(f"{source}: label(s) {', '.join(unknown[:3])} match no photo; check the folders "
                               "given, or remove those rows")
        amb = sorted({k for k in keys if k in dup})
        if amb:
            raise FlexcalError(f"{source}: label {amb[0]} matches photos in several trials; give one trial and "
                               "its reference at a time")
        g = ref.assign(key=keys).groupby("key")["angle_deg"]
        stats = pd.DataFrame({"reference_deg": g.mean(), "reference_sd_deg": g.std(), "reference_n": g.count()})
        rows = [stats.loc[n] if n in stats.index else pd.Series({"reference_deg": np.nan, "reference_sd_deg": np.nan,
                                                                  "reference_n": 0}) for n in names]
        out = pd.DataFrame(rows).reset_index(drop=True)
        how = f"{len(ref)} reference rows mapped to {int((out['reference_n'] > 0).sum())} photos by Label"
    else:
        n_rows, n_img = len(ref), len(images)
        if n_rows == 0 or n_rows % n_img:
            raise FlexcalError(f"{source}: {n_rows} row(s) for {n_img} photo(s); without a Label column the rows map "
                               "to the photos in sorted order, so the counts must match (add Labels, or delete the "
                               "extra rows)")
        k = n_rows // n_img
        a = ref["angle_deg"].to_numpy(float).reshape(n_img, k)
        out = pd.DataFrame({"reference_deg": a.mean(axis=1), "reference_sd_deg": a.std(axis=1, ddof=1) if k > 1
                            else np.nan, "reference_n": k})
        how = (f"{n_rows} reference rows mapped to {n_img} photos in sorted order"
               + (f", {k} consecutive rows per photo (repeated measurements, averaged)" if k > 1 else ""))
    out.insert(0, "image", [str(p) for p in images])
    return out, how


def bland_altman(diff, mean=None) -> dict:
    """Bias and 95 % limits of agreement (bias ± 1.96 sd) of paired differences, with the bias's 95 % CI."""
    d = np.asarray(diff, float)
    d = d[np.isfinite(d)]
    n = d.size
    if n < 2:
        return {"n": int(n), "bias_deg": float(d.mean()) if n else float("nan"), "sd_deg": float("nan"),
                "loa_low_deg": float("nan"), "loa_high_deg": float("nan"), "bias_ci_deg": [float("nan")] * 2}
    bias, sd = float(d.mean()), float(d.std(ddof=1))
    from scipy import stats

    half = float(stats.t.ppf(0.975, n - 1) * sd / np.sqrt(n))
    return {"n": int(n), "bias_deg": bias, "sd_deg": sd, "loa_low_deg": bias - 1.96 * sd,
            "loa_high_deg": bias + 1.96 * sd, "bias_ci_deg": [bias - half, bias + half],
            "mae_deg": float(np.mean(np.abs(d))), "max_abs_deg": float(np.max(np.abs(d)))}


def plot_bland_altman(comp: pd.DataFrame, ba: dict, path, *, label="flexcal − reference") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = comp["difference_deg"].notna()
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.scatter(comp.loc[ok, "mean_deg"], comp.loc[ok, "difference_deg"], s=14)
    for y, style, text in ((ba["bias_deg"], "-", f"bias {ba['bias_deg']:+.2f}°"),
                           (ba["loa_low_deg"], "--", f"−1.96 sd {ba['loa_low_deg']:+.2f}°"),
                           (ba["loa_high_deg"], "--", f"+1.96 sd {ba['loa_high_deg']:+.2f}°")):
        if np.isfinite(y):
            ax.axhline(y, color="C1", ls=style, lw=1)
            ax.text(ax.get_xlim()[1], y, " " + text, va="center", fontsize=8, color="C1")
    ax.axhline(0, color="0.6", lw=0.8)
    ax.set(xlabel="mean of the two [deg]", ylabel=f"{label} [deg]",
           title=f"Bland–Altman: {ba['n']} photos")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def remeasure(dirs, out_dir, *, reference=None, jobs=None, worst: int = 12, progress: bool = True) -> dict:
    """Measure every photo of the trial folders; with a reference, compare.

    Writes into ``out_dir``: ``angles.csv``, ``overlays/`` (+ contact sheet) and, with
    a reference, ``comparison.csv`` (COMPARISON_COLUMNS, the worst disagreements first),
    ``bland_altman.png``, ``worst.png`` (contact sheet of the photos that disagree most)
    and ``summary.json``. Returns the summary.
    """
    import json

    import cv2

    from flexcal import __version__
    from flexcal.capture.imagej import read_reference
    from flexcal.measure import measure_files, overlay_names, photo_labels
    from flexcal.vision.overlay import contact_sheet

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    images = trial_images(dirs)
    ref = read_reference(reference) if reference is not None else None   # fail before the slow part
    ov_dir = out / "overlays"
    angles = measure_files(images, jobs=jobs, overlay_dir=ov_dir, progress=progress)
    angles.to_csv(out / "angles.csv", index=False, float_format="%.4f")
    summary = {"flexcal_version": __version__, "trials": [str(d) for d in dirs], "photos": len(images),
               "status": angles["status"].value_counts().to_dict()}
    if ref is None:
        (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
        return summary
    mapped, how = map_reference(ref, images, str(reference))
    comp = angles[["image", "angle_deg", "angle_unc_deg", "status", "reason"]].merge(mapped, on="image", how="left")
    answered = comp["status"] != "failed"
    comp["difference_deg"] = np.where(answered, comp["angle_deg"] - comp["reference_deg"], np.nan)
    comp["mean_deg"] = np.where(answered, (comp["angle_deg"] + comp["reference_deg"]) / 2, np.nan)
    comp["overlay"] = [str(ov_dir / n) for n in overlay_names(images)]
    label = dict(zip(comp["image"], photo_labels(images)))
    comp = comp.iloc[np.argsort(-comp["difference_deg"].abs().fillna(-1).to_numpy(), kind="stable")]
    comp[COMPARISON_COLUMNS].to_csv(out / "comparison.csv", index=False, float_format="%.4f")
    ba = bland_altman(comp["difference_deg"])
    plot_bland_altman(comp, ba, out / "bland_altman.png")
    top = comp[comp["difference_deg"].notna()].head(worst)
    thumbs, labels, states = [], [], []
    for _, r in top.iterrows():
        img = cv2.imread(r["overlay"], cv2.IMREAD_REDUCED_COLOR_2)
        if img is not None:
            thumbs.append(img)
            labels.append(f"{label[r['image']]}: {r['angle_deg']:.1f} vs {r['reference_deg']:.1f} "
                          f"({r['difference_deg']:+.1f})")
            states.append(r["status"])
    if thumbs:
        cv2.imwrite(str(out / "worst.png"), contact_sheet(thumbs, labels, states))
    summary.update({"reference": str(reference), "mapping": how, "bland_altman": ba,
                    "not_compared": int(comp["difference_deg"].isna().sum()),
                    "worst": top[["image", "angle_deg", "reference_deg", "difference_deg"]].to_dict(orient="records")})
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=float) + "\n")
    return summary
