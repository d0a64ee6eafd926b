"""The ``flexcal`` command: thin argument parsing around the library."""

from __future__ import annotations

import argparse
import os
import sys

from flexcal import __version__
from flexcal.errors import FlexcalError


def parse_angles(text: str) -> tuple[float, ...]:
    """``start:stop:step`` (stop included) or a comma list, in degrees."""
    try:
        if ":" in text:
            parts = [float(x) for x in text.split(":")]
            if len(parts) != 3 or parts[2] <= 0:
                raise ValueError
            start, stop, step = parts
            n = int(round((stop - start) / step))
            if n < 0:
                raise ValueError
            return tuple(round(start + i * step, 9) for i in range(n + 1))
        return tuple(float(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not an angle list; write start:stop:step (e.g. 0:90:10) or a comma list (e.g. 0,30,60)"
        ) from None


def parse_size(text: str) -> tuple[int, int]:
    """``WIDTHxHEIGHT`` in pixels, returned as (height, width)."""
    try:
        w, h = (int(x) for x in text.lower().split("x"))
        if w < 16 or h < 16:
            raise ValueError
        return h, w
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an image size; write WIDTHxHEIGHT, e.g. 1280x960") from None


def cmd_render(args) -> int:
    from pathlib import Path

    from flexcal.synthetic.trial import write_experiment

    out = Path(args.out)
    if out.exists() and any(out.iterdir()) and not args.force:
        raise FlexcalError(f"--out {out}: folder is not empty; choose a new folder or add --force to write into it")
    summary = write_experiment(out, trials=args.trials, angles_deg=args.angles, difficulty=args.difficulty,
                               seed=args.seed, shape=args.size, jpeg_quality=args.jpeg_quality)
    n = sum(t["photos"] for t in summary["trials"])
    print(f"wrote {len(summary['trials'])} trial folder(s) with {n} photos and pressure.csv to {out}")
    return 0


def parse_roi(text: str) -> tuple[int, int, int, int]:
    """``x,y,w,h`` in pixels."""
    try:
        x, y, w, h = (int(v) for v in text.split(","))
        if w <= 0 or h <= 0 or x < 0 or y < 0:
            raise ValueError
        return x, y, w, h
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a region; write x,y,w,h in pixels, e.g. 100,50,800,600") from None


def cmd_measure(args) -> int:
    from pathlib import Path

    from flexcal.capture.images import find_images
    from flexcal.measure import measure_files, unsure_lines

    files = find_images(args.paths, all_files=True)
    if not files:
        raise FlexcalError(f"no files found in {' '.join(args.paths)}; give photos, folders or a glob such as 'trial_*/images'")
    df = measure_files(files, roi=args.roi, method=args.method, jobs=args.jobs, overlay_dir=args.overlays)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(out, index=False, float_format="%.4f")
    counts = df["status"].value_counts()
    print(f"measured {len(df)} photo(s): " + ", ".join(f"{counts.get(k, 0)} {k}" for k in ("ok", "low_confidence", "failed"))
          + f"; angles table: {out}" + (f"; overlays: {args.overlays}" if args.overlays else ""))
    for line in unsure_lines(df, out):
        print(line)
    return 0


def cmd_remeasure(args) -> int:
    from pathlib import Path

    import pandas as pd

    from flexcal.measure import unsure_lines
    from flexcal.remeasure import remeasure

    s = remeasure(args.trials, args.out, reference=args.reference, jobs=args.jobs, worst=args.worst)
    st = s["status"]
    table = Path(args.out) / "angles.csv"
    print(f"re-measured {s['photos']} photo(s): " + ", ".join(f"{st.get(k, 0)} {k}" for k in
                                                            ("ok", "low_confidence", "failed"))
          + f"; angles: {table}, overlays: {Path(args.out) / 'overlays'}")
    for line in unsure_lines(pd.read_csv(table), table):
        print(line)
    if "bland_altman" in s:
        b = s["bland_altman"]
        print(f"against {args.reference} ({s['mapping']}): {b['n']} compared, {s['not_compared']} not; "
              f"bias {b['bias_deg']:+.2f} deg, limits of agreement {b['loa_low_deg']:+.2f} ... {b['loa_high_deg']:+.2f} "
              f"deg, MAE {b.get('mae_deg', float('nan')):.2f} deg")
        print(f"per photo (worst first): {args.out}/comparison.csv; plot: {args.out}/bland_altman.png; "
              f"worst photos: {args.out}/worst.png")
    return 0


def cmd_capture(args) -> int:
    from flexcal.capture.frames import FrameSource
    from flexcal.capture.serial_reader import SerialReader
    from flexcal.capture.session import TrialRecorder, run_capture

    frames = FrameSource(args.camera, fps=args.fps)
    try:
        reader = SerialReader(args.port, baud=args.baud, reconnect=True).start()   # a bad port fails before any file
    except FlexcalError:
        frames.close()
        raise
    try:
        recorder = TrialRecorder(args.out, meta={"port": args.port, "baud": args.baud, "camera": str(args.camera),
                                                 "mode": "manual" if args.manual else "auto", "hold_s": args.hold_s,
                                                 "steps_deg": list(args.steps)})
        frames.start()
        try:
            s = run_capture(reader, frames, recorder, args.steps, mode="manual" if args.manual else "auto",
                            hold_s=args.hold_s, step_timeout_s=args.step_timeout_s)
        except FlexcalError:
            recorder.finish()
            raise
    finally:
        reader.close()
        frames.close()
    clock = s["clock_fit"] or {}
    jit = clock.get("latency_after_fit", {})
    print(f"recorded {s['photos']} photo(s) and {s['samples']} samples in {args.out}"
          + (f"; clock drift {clock['drift_ppm']:+.0f} ppm, USB latency after the fit median "
             f"{1000 * jit['median_s']:.1f} ms, p95 {1000 * jit['p95_s']:.1f} ms" if clock else "")
          + (f"; {s['unreadable_lines']} unreadable line(s)" if s["unreadable_lines"] else ""))
    print(f"next: calibrate --images {args.out}/images --log {args.out}/serial.csv")
    return 0


def cmd_monitor(args) -> int:
    import time

    from flexcal.capture.protocol import Comment, Sample
    from flexcal.capture.serial_reader import SerialReader
    from flexcal.capture.session import parse_live_line

    cal = None
    if args.calibration:
        from flexcal.calibration import load

        cal = load(args.calibration)
    end = time.monotonic() + args.duration if args.duration else None
    with SerialReader(args.port, baud=args.baud, reconnect=True) as reader:
        print("t_host_s,t_ms,resistance_ohm,angle_deg" + (",angle_corrected_deg" if cal else ""), flush=True)
        while end is None or time.monotonic() < end:
            item = reader.get(timeout=0.1)
            if item is None or not hasattr(item, "text"):
                if item is not None:
                    print(f"# {item.kind}: {item.detail}", flush=True)
                continue
            try:
                p = parse_live_line(item.text)
            except ValueError:
                print(f"# unreadable: {item.text[:60]!r}", flush=True)
                continue
            if isinstance(p, Comment):
                print(f"# {p.text}", flush=True)
            elif isinstance(p, Sample):
                row = f"{item.t_host_s:.3f},{p.t_ms if p.t_ms >= 0 else ''},{p.resistance_ohm:.1f},{p.angle_deg:.2f}"
                if cal is not None:
                    a = float(cal.angle_deg(p.resistance_ohm, extrapolate=True))
                    row += f",{a:.2f}"
                print(row, flush=True)
    return 0


def _divider(args):
    from flexcal.divider import Divider

    if args.r_fixed_ohm is None:
        return None
    try:
        return Divider(args.r_fixed_ohm, args.vref_v, args.adc_bits)
    except ValueError as e:
        raise FlexcalError(f"--r-fixed-ohm/--vref-v/--adc-bits: {e}") from None


def cmd_calibrate(args) -> int:
    from flexcal.calibration.calibrate import calibrate
    from flexcal.calibration.experiment import find_trials, read_angles, trials_from_args

    if args.trials and (args.images or args.log):
        raise FlexcalError("give either --trials DIR, or --images DIR --log FILE, not both")
    if not args.trials and not (args.images and args.log):
        raise FlexcalError("say where the experiment is: --images DIR --log serial.csv (one pair per trial), "
                           "or --trials DIR (a folder of trial folders)")
    trials = find_trials(args.trials) if args.trials else trials_from_args(args.images, args.log)
    angles = read_angles(args.angles) if args.angles else None
    res = calibrate(trials, args.out, angles=angles, angles_path=args.angles, pressure_path=args.pressure,
                    contact_area_in2=args.contact_area_in2, divider=_divider(args), window_s=args.window_s,
                    jobs=args.jobs, overlays=not args.no_overlays)
    val = {v["mapping"]: v for v in res["validation"]}
    print(f"calibrated {len(trials)} trial(s): {res['pairs']['used']} of {res['pairs']['total']} pairs used"
          + (f" ({len(res['pairs']['excluded'])} excluded, reasons in the report)" if res["pairs"]["excluded"] else ""))
    for name in ("factory", "empirical", "physical"):
        if name in val:
            v = val[name]
            print(f"  {name:9s} angle RMSE {v['rmse_deg']:5.2f} deg, bias {v['bias_deg']:+5.2f}, "
                  f"max {v['max_abs_deg']:5.2f}  ({v['validation']})")
    p = res["paths"]
    print(f"report: {p['report']}\ncalibration: {p['calibration']}   firmware header: {p['header']}")
    return 0


def cmd_apply(args) -> int:
    from flexcal.calibration.calibrate import apply_calibration

    df = apply_calibration(args.calibration, args.log, args.out, mapping=args.mapping,
                           extrapolate=args.extrapolate, divider=_divider(args))
    extra = int(df["extrapolated"].sum())
    print(f"wrote {len(df)} sample(s) with corrected angles to {args.out}"
          + (f"; {extra} outside the calibrated range (extrapolated)" if extra else ""))
    return 0


def _add_divider_args(p):
    g = p.add_argument_group("voltage divider (for logs with ADC counts only and no firmware banner)")
    g.add_argument("--r-fixed-ohm", type=float, help="the divider's fixed resistor, ohm")
    g.add_argument("--vref-v", type=float, default=5.0, help="ADC reference voltage (default 5)")
    g.add_argument("--adc-bits", type=int, default=10, help="ADC resolution (default 10)")


def add_calibrate_args(p):
    p.add_argument("--images", nargs="+", metavar="DIR", help="folder(s) of a trial's photos (globs allowed)")
    p.add_argument("--log", nargs="+", metavar="FILE", help="serial log(s), one per --images folder, same order")
    p.add_argument("--trials", nargs="+", metavar="DIR", help="experiment folder(s) holding trial folders "
                   "(images/ + serial.csv [+ frames.csv]), or trial folders")
    p.add_argument("--angles", metavar="CSV", help="use these photo angles (image,angle_deg; e.g. from flexcal "
                   "measure) instead of measuring the photos")
    p.add_argument("--pressure", metavar="CSV", help="the pressure experiment: mass_g,trial,angle_deg,resistance_ohm")
    p.add_argument("--contact-area-in2", type=float, default=0.05, help="pad contact area, in² (default 0.05)")
    p.add_argument("--out", default="calibration", metavar="DIR", help="output folder (default ./calibration)")
    p.add_argument("--window-s", type=float, default=2.0, help="window around each photo's time, s (default 2)")
    p.add_argument("--jobs", type=int, default=None, help="parallel processes for the photos (default: one per core)")
    p.add_argument("--no-overlays", action="store_true", help="do not draw an overlay per photo")
    _add_divider_args(p)
    p.set_defaults(func=cmd_calibrate)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="flexcal", description="Calibrate a flex-sensor glove from photos and serial logs.")
    parser.add_argument("--version", action="version", version=f"flexcal {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("render", help="write a synthetic experiment (trial folders + pressure.csv) with known truth")
    p.add_argument("--out", required=True, help="folder to write (must be new or empty unless --force)")
    p.add_argument("--trials", type=int, default=5, help="number of trials (default 5)")
    p.add_argument("--angles", type=parse_angles, default=tuple(range(0, 91, 10)),
                   help="step angles in degrees, start:stop:step or a comma list (default 0:90:10)")
    p.add_argument("--difficulty", choices=["clean", "realistic", "hard"], default="realistic")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--size", type=parse_size, default=(960, 1280), help="photo size WIDTHxHEIGHT (default 1280x960)")
    p.add_argument("--jpeg-quality", type=int, default=90, choices=range(1, 101), metavar="1..100")
    p.add_argument("--force", action="store_true", help="write into a non-empty folder")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("measure", help="measure the bend angle in photos (angles table, overlays, contact sheet)")
    p.add_argument("paths", nargs="+", metavar="PATH", help="photos, folders of photos, or globs")
    p.add_argument("--out", default="angles.csv", help="angles table to write (default angles.csv)")
    p.add_argument("--overlays", metavar="DIR", help="write an overlay per photo and contact_sheet.png here")
    p.add_argument("--roi", type=parse_roi, help="only look inside x,y,w,h (pixels)")
    p.add_argument("--method", choices=["auto", "contour", "markers"], default="auto")
    p.add_argument("--jobs", type=int, default=None, help="parallel processes (default: one per core)")
    p.set_defaults(func=cmd_measure)

    p = sub.add_parser("capture", help="record a trial: photos and serial readings on one clock")
    p.add_argument("--port", required=True, help="serial port (/dev/ttyACM0, COM3) or pyserial URL (socket://, loop://)")
    p.add_argument("--camera", required=True, help="camera index (0), a video file, or a folder of images")
    p.add_argument("--out", required=True, metavar="TRIAL_DIR", help="new trial folder to write")
    p.add_argument("--steps", type=parse_angles, default=tuple(range(0, 91, 10)),
                   help="step angles in degrees, start:stop:step or a list (default 0:90:10)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--auto", action="store_true", help="photo once the reading is steady (default)")
    mode.add_argument("--manual", action="store_true", help="photo when you press Enter")
    p.add_argument("--hold-s", type=float, default=1.0, help="auto: steady this long before the photo (default 1)")
    p.add_argument("--baud", type=int, default=115200)
    p.add_argument("--fps", type=float, default=None, help="frame rate of a video file or image folder")
    p.add_argument("--step-timeout-s", type=float, default=None,
                   help="give up (keeping what was recorded) when a step takes longer than this")
    p.set_defaults(func=cmd_capture)

    p = sub.add_parser("monitor", help="print the glove's live stream (with --calibration, corrected angles too)")
    p.add_argument("--port", required=True, help="serial port or pyserial URL")
    p.add_argument("--calibration", metavar="JSON", help="calibration.json for a corrected-angle column")
    p.add_argument("--baud", type=int, default=115200)
    p.add_argument("--duration", type=float, default=None, help="stop after this many seconds")
    p.set_defaults(func=cmd_monitor)

    p = sub.add_parser("remeasure", help="re-measure old trials' photos and compare with a hand-measured reference")
    p.add_argument("trials", nargs="+", metavar="TRIAL_DIR", help="trial folders (photos in images/ or in the folder)")
    p.add_argument("--reference", metavar="FILE", help="ImageJ Results (.csv/.txt) or an image,angle_deg CSV")
    p.add_argument("--out", default="remeasure", metavar="DIR", help="output folder (default ./remeasure)")
    p.add_argument("--worst", type=int, default=12, help="how many of the most disagreeing photos to show")
    p.add_argument("--jobs", type=int, default=None, help="parallel processes (default: one per core)")
    p.set_defaults(func=cmd_remeasure)

    p = sub.add_parser("calibrate", help="measure photos, pair them with the serial log, fit, validate, report")
    add_calibrate_args(p)

    p = sub.add_parser("apply", help="add corrected angles to a serial log with a calibration.json")
    p.add_argument("--calibration", required=True, metavar="JSON", help="calibration.json from calibrate")
    p.add_argument("--log", required=True, metavar="FILE", help="serial log to correct (any dialect read_log reads)")
    p.add_argument("--out", required=True, metavar="CSV", help="the log with corrected-angle columns")
    p.add_argument("--mapping", choices=["empirical", "physical", "factory"],
                   help="mapping for angle_corrected_deg (default: the calibration's recommended one)")
    p.add_argument("--extrapolate", action="store_true", help="map readings outside the calibrated range too")
    _add_divider_args(p)
    p.set_defaults(func=cmd_apply)
    return parser


# The commands measure photos in a process per core (``measure.measure_files``): OpenCV
# and numpy's BLAS (OpenBLAS) would start a thread pool in every one of them, and the
# pools contend for the same cores (two processes on two cores, 120 benchmark photos:
# 11-13 photos/s with the pools, 14-20 without; the same answers; one process alone is
# as fast either way). The libraries read these when first loaded, which the commands
# do lazily, after this; a number the user chose is kept.
SINGLE_THREADED = ("OPENCV_FOR_THREADS_NUM", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def main(argv=None) -> int:
    for var in SINGLE_THREADED:
        os.environ.setdefault(var, "1")
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except FlexcalError as e:
        print(f"flexcal {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"flexcal {args.command}: interrupted; files written so far are kept", file=sys.stderr)
        return 130


def calibrate_main(argv=None) -> int:
    """The ``calibrate`` console script: the same as ``flexcal calibrate``."""
    return main(["calibrate", *(sys.argv[1:] if argv is None else argv)])


if __name__ == "__main__":
    sys.exit(main())
