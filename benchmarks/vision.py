"""Accuracy and speed of flexcal.vision on seeded rendered suites.

    python benchmarks/vision.py [--n 100] [--size 1280x960] [--suites clean,realistic,hard,drawn,cluttered]
                                [--details results.csv] [--orientations] [--kmeans-seed 0] [--markers]
                                [--glove black] [--palm-mm 5,10] [--tape on|off]

Per suite: MAE, median, P95 and maximum absolute error over answered images (status
ok or low_confidence), the share answered, silent gross errors (answered with an error
over 5 deg), the share whose true angle lies within 2 sigma, and images per second per
process (JPEG decoding included). Renders are written as JPEG (quality 90) and read
back, as a user's photos would be. ``--details`` writes one row per render (truth, answer,
uncertainty, status, reason, the render's nuisances and the measurement's own figures,
``detail_*``) to find what fails, and how well a new check would tell right answers from
wrong ones; two such files of the same run, before and after a change, are compared row
by row by ``benchmarks/compare.py``.
The suites clean, realistic and hard are ``flexcal.synthetic.render_finger``'s presets;
drawn is ``flexcal.synthetic.drawn``: fingers drawn another way, which the method was not
built on, to show whether it holds beyond the renderer it was developed with; cluttered
is the same with a striped background, the middle finger behind the index and the
sensor's lead, each at random.
``--orientations`` measures every render also turned by 90, 180 and 270 deg and mirrored
(suites named ``clean x5`` and so on): the bend is the same, and a method that holds in
any orientation answers them alike; k-means starts and JPEG blocks differ, so this also
shows how much an answer hangs on the particular photo. Each suite's row then ends with
how alike the turns were: the share of renders answered in all five photos or in none,
and the median spread (largest answer minus smallest) of a render's answers.
``--kmeans-seed`` measures the same photos with another random start of the colour
clustering: another draw of colour clusters, as another photo of the scene could give;
the share answered and any silent error on several draws say more than one draw does.
``--markers`` renders three coloured dots on every finger (proximal, joint, distal) and
prints, per suite, the share measured from the dots (the rest from the outline).
``--glove NAME`` puts that glove (``flexcal.synthetic.GLOVES``) on every rendered
finger, the other nuisances as drawn. Every preset's hand has a palm, thicker than the
finger at the knuckle by 5 to 10 mm (real hands: about that); ``--palm-mm LO,HI`` draws
it from LO to HI mm instead (per render from a stream of its own, so the other nuisances
are the presets' own), and ``--palm-mm 0,0`` renders hands without one, as the presets
did until 2026-11-27. ``--tape on`` puts the sensor's two tape bands (one on the finger,
one on the back of the hand; about half the realistic renders have them) on every rendered
finger, ``--tape off`` on none, the other nuisances as drawn: what the bands cost.
"""

from __future__ import annotations

import argparse
import csv
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from flexcal.measure import measure_photo
from flexcal.synthetic import render_finger
from flexcal.synthetic.drawn import draw_finger
from flexcal.synthetic.render import GLOVES
from flexcal.vision import angle as vision_angle


SUITES = ("clean", "realistic", "hard", "drawn", "cluttered")   # the last two: flexcal.synthetic.drawn
DRAWN = ("drawn", "cluttered")

# the same photo turned and mirrored: the bend is the same (--orientations)
ORIENTATIONS = {"": lambda im: im,
                "r90": lambda im: cv2.rotate(im, cv2.ROTATE_90_CLOCKWISE),
                "r180": lambda im: cv2.rotate(im, cv2.ROTATE_180),
                "r270": lambda im: cv2.rotate(im, cv2.ROTATE_90_COUNTERCLOCKWISE),
                "mirror": lambda im: np.ascontiguousarray(im[:, ::-1])}


def diagnostics(m) -> dict:
    """The measurement's own figures (``AngleMeasurement.details``) that are single
    numbers, flags or words, as ``detail_<name>`` columns: the taper of the arms' edges,
    the knuckle's distance from the tip, the hand's width over the finger's, why no
    finger was found, ... (those of the silhouette the answer or refusal came from, as
    far as it got; pixels of the photo as read, at half size for a 1280x960 JPEG). They
    show how well a check would tell right answers from wrong ones over a whole run."""
    def plain(v):
        return v if isinstance(v, (bool, str)) else bool(v) if isinstance(v, np.bool_) else float(v)
    return {f"detail_{k}": plain(v) for k, v in m.details.items()
            if isinstance(v, (int, float, str, np.integer, np.floating, np.bool_))}


def run_suite(difficulty, n, shape, seed, tmp, orientations=False, markers=False, glove=None, palm_mm=None,
              tape=None):
    rng = np.random.default_rng(seed)
    palm_rng = np.random.default_rng([seed, 1])     # (its own stream: the renders' other draws stay as they are)
    files, truth, params = [], [], []
    for i in range(n):
        a = float(rng.uniform(0, 90))
        if difficulty in DRAWN:   # a photo-like drawing, compressed once already
            img, t = draw_finger(a, shape=shape, rng=int(rng.integers(2**31)), cluttered=difficulty == "cluttered")
        else:
            extra = {} if glove is None else {"glove": glove}
            if tape is not None:
                extra["tape"] = tape
            if palm_mm is not None:
                extra["palm_mm"] = float(palm_rng.uniform(*palm_mm))
            img, t = render_finger(a, shape=shape, rng=int(rng.integers(2**31)), difficulty=difficulty,
                                   jpeg_quality=None, markers=markers, **extra)
        # the truth's angle and vertex under their own names, beside the measured ones
        # (the vertex of the render as drawn, not turned)
        p = {(f"true_{k}" if k in ("angle_deg", "vertex_x", "vertex_y") else k): v for k, v in t.as_dict().items()}
        for name, turn in (ORIENTATIONS.items() if orientations else [("", ORIENTATIONS[""])]):
            f = Path(tmp) / f"{difficulty}_{i:04d}{'_' + name if name else ''}.jpg"
            cv2.imwrite(str(f), turn(img), [cv2.IMWRITE_JPEG_QUALITY, 90])
            files.append(f)
            truth.append(a)
            params.append({**p, "orientation": name or "as rendered"})
    t0 = time.perf_counter()
    rows = []
    for f in files:
        m, _, _ = measure_photo(f)      # as `flexcal measure` reads and measures a photo
        rows.append({"image": f.name, **m.row(), **diagnostics(m)})
    dt = time.perf_counter() - t0
    details = [{"suite": difficulty, "index": i, **rows[i], "error_deg": rows[i]["angle_deg"] - truth[i],
                **params[i]} for i in range(len(files))]
    got = np.array([r["angle_deg"] for r in rows])
    unc = np.array([r["angle_unc_deg"] for r in rows])
    truth = np.array(truth)
    answered = np.isfinite(got)
    err = np.abs(got - truth)[answered]
    return {
        "suite": (difficulty + (f"/{glove}" if glove else "")
                  + (f"+palm{palm_mm[0]:g}-{palm_mm[1]:g}" if palm_mm is not None else "")
                  + ({True: "+tape", False: "-tape"}.get(tape, ""))
                  + (" x5" if orientations else "")),
        "n": len(files),
        "MAE": err.mean() if err.size else np.nan, "median": np.median(err) if err.size else np.nan,
        "P95": np.percentile(err, 95) if err.size else np.nan, "max": err.max() if err.size else np.nan,
        "answered": answered.mean(), "gross>5": int((err > 5).sum()),
        "within2sigma": float(np.mean(err <= 2 * unc[answered])) if err.size else np.nan,
        "img/s": len(files) / dt, "details": details,
        "by markers": float(np.mean([r["method"] == "markers" for r in rows])),
        **(turns_alike(got) if orientations else {}),
    }


def turns_alike(got) -> dict:
    """How alike the five photos of each render (as rendered, turned, mirrored: ``got``,
    the answers in that order, NaN where refused) were measured: the share of renders
    answered in all five or in none ("alike"), and the median, over renders answered at
    least twice, of the spread (largest answer minus smallest)."""
    per_render = np.asarray(got, float).reshape(-1, len(ORIENTATIONS))
    answered = np.isfinite(per_render)
    spreads = [np.ptp(a[ok]) for a, ok in zip(per_render, answered) if ok.sum() >= 2]
    return {"alike": float(np.mean(answered.all(axis=1) | ~answered.any(axis=1))),
            "spread": float(np.median(spreads)) if spreads else float("nan")}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--size", default="1280x960")
    ap.add_argument("--suites", help="comma-separated, of " + ", ".join(SUITES) + " (default: all; with --markers, "
                    "the renderer's); each suite renders the same photos whichever others are run")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--kmeans-seed", type=int, default=0,
                    help="random start of the colour clustering (0, as `flexcal measure` uses); other values are "
                         "other draws of the same photos' colour clusters, to see how much the answers depend on it")
    ap.add_argument("--details", type=Path, help="write one row per render to this CSV")
    ap.add_argument("--orientations", action="store_true",
                    help="also measure each render turned by 90, 180 and 270 deg and mirrored (5 photos each)")
    ap.add_argument("--markers", action="store_true",
                    help="render three coloured marker dots on every finger; prints the share measured from them")
    ap.add_argument("--glove", choices=[g for g in GLOVES if g],
                    help="put this glove on every rendered finger (the suites clean, realistic, hard)")
    ap.add_argument("--palm-mm", metavar="LO,HI",
                    help="draw every rendered hand's palm LO to HI mm thicker than the finger at the knuckle, "
                         "instead of the presets' 5 to 10 (real hands: about that); 0,0: no palm")
    ap.add_argument("--tape", choices=["on", "off"],
                    help="tape bands on every rendered finger, or on none (the suites clean, realistic, hard)")
    args = ap.parse_args(argv)
    palm_mm = None
    if args.palm_mm is not None:
        try:
            palm_mm = tuple(float(v) for v in args.palm_mm.split(","))
            ok = len(palm_mm) == 2 and 0 <= palm_mm[0] <= palm_mm[1] <= 40
        except ValueError:
            ok = False
        if not ok:
            ap.error(f"--palm-mm: expected LO,HI in mm with 0 <= LO <= HI <= 40, e.g. 5,10; got {args.palm_mm!r}")
    tape = None if args.tape is None else args.tape == "on"
    vision_angle.KMEANS_SEED = args.kmeans_seed
    details = []
    w, h = (int(v) for v in args.size.split("x"))
    suites = (args.suites.split(",") if args.suites
              else [s for s in SUITES
                    if not ((args.markers or args.glove or palm_mm is not None or tape is not None) and s in DRAWN)])
    for suite in suites:       # every suite checked before the first is run
        if suite not in SUITES:
            ap.error(f"--suites: unknown suite {suite!r}; choose from {', '.join(SUITES)}")
        for flag, what in ((args.markers, "--markers: the {} suite has no marker dots"),
                           (args.glove, "--glove: the {} suite is drawn, not rendered with a glove"),
                           (palm_mm is not None, "--palm-mm: the {} suite is drawn, not rendered with a palm"),
                           (tape is not None, "--tape: the {} suite is drawn, not rendered with tape bands")):
            if flag and suite in DRAWN:
                ap.error(what.format(suite) + "; choose from clean, realistic, hard")
    print(f"flexcal.vision benchmark: {args.n} renders per suite at {w}x{h}, JPEG q90, seed {args.seed}"
          + (f", k-means seed {args.kmeans_seed}" if args.kmeans_seed else ""))
    print(f"{'suite':<16} {'MAE':>6} {'median':>7} {'P95':>6} {'max':>6} {'answered':>9} {'gross>5':>8} "
          f"{'in 2sig':>8} {'img/s':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for suite in suites:
            # each suite's own seed (seed, seed + 1, seed + 2), not its place in the list
            r = run_suite(suite, args.n, (h, w), args.seed + SUITES.index(suite), tmp, args.orientations, args.markers,
                          args.glove, palm_mm, tape)
            print(f"{r['suite']:<16} {r['MAE']:6.2f} {r['median']:7.2f} {r['P95']:6.2f} {r['max']:6.1f} "
                  f"{r['answered']:9.1%} {r['gross>5']:8d} {r['within2sigma']:8.1%} {r['img/s']:6.1f}"
                  + (f"   from the dots: {r['by markers']:.0%}" if args.markers else "")
                  + (f"   turns: {r['alike']:.0%} of renders answered alike, median spread {r['spread']:.2f} deg"
                     if args.orientations else ""), flush=True)
            details += r["details"]
    if args.details:
        with open(args.details, "w", newline="") as fh:
            # the renderer's and the drawings' truths name different nuisances: every column
            # any suite has, empty where a suite has none
            writer = csv.DictWriter(fh, fieldnames=list(dict.fromkeys(k for row in details for k in row)), restval="")
            writer.writeheader()
            writer.writerows(details)
        print(f"per-render rows: {args.details}")


if __name__ == "__main__":
    main()
