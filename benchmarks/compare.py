"""Row by row: what a change to flexcal.vision did to the benchmark's answers.

    python benchmarks/compare.py BEFORE.csv AFTER.csv [--moved 0.5] [--silent 5]

BEFORE and AFTER are ``benchmarks/vision.py --details`` files of the same run (the same
seed, suites and options) with the code before and after a change. Per suite it prints
how many photos were answered and how many answers were over ``--silent`` degrees off
(silent gross errors) before and after; then every photo whose outcome changed: newly
answered (with its error), newly refused (with the reason), answers that moved by more
than ``--moved`` degrees, and silent errors that appeared or went. A change is judged by
these rows, not by the suite's totals: a fix that answers five photos and makes one
silent error elsewhere nets out as a gain in the totals.
"""

from __future__ import annotations

import argparse
import sys

import pandas as pd

KEY = ["suite", "image"]


def _read(path, ap):
    try:
        df = pd.read_csv(path)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as e:
        why = " ".join(str(e).split())
        ap.error(f"{path}: cannot read it ({why}); give a CSV written by benchmarks/vision.py --details")
    missing = [c for c in KEY + ["angle_deg", "angle_unc_deg", "status", "reason", "true_angle_deg"]
               if c not in df.columns]
    if missing:
        ap.error(f"{path}: no column {', '.join(missing)}; give a CSV written by benchmarks/vision.py --details")
    df["answered"] = df["status"] != "failed"
    df["error"] = (df["angle_deg"] - df["true_angle_deg"]).abs()
    return df.set_index(KEY)


def compare(before: pd.DataFrame, after: pd.DataFrame, moved: float, silent: float) -> list[str]:
    """The report's lines for two ``--details`` tables indexed by (suite, image)."""
    lines = []
    both = before.merge(after, left_index=True, right_index=True, how="inner", suffixes=("_b", "_a"))
    only = len(before.index.symmetric_difference(after.index))
    if only:
        lines.append(f"note: {only} rows are in one file only (another seed, suite or option?); "
                     "only the rows in both are compared")
    lines.append(f"{'suite':<16} {'rows':>5} {'answered before':>16} {'after':>6} "
                 f"{'silent before':>14} {'after':>6}")
    for suite, g in both.groupby(level="suite", sort=False):
        sb = int((g["answered_b"] & (g["error_b"] > silent)).sum())
        sa = int((g["answered_a"] & (g["error_a"] > silent)).sum())
        lines.append(f"{suite:<16} {len(g):5d} {g['answered_b'].mean():16.1%} {g['answered_a'].mean():6.1%} "
                     f"{sb:14d} {sa:6d}")

    def row(idx, r, what):
        suite, image = idx
        return f"  {suite} {image}, truth {r['true_angle_deg_a']:.1f} deg: {what}"

    def answer(r, side):
        return f"{r['angle_deg_' + side]:.1f} +- {r['angle_unc_deg_' + side]:.1f} deg, {r['status_' + side]}"

    groups = {
        "newly answered": both["answered_a"] & ~both["answered_b"],
        "newly refused": both["answered_b"] & ~both["answered_a"],
        f"answers moved by more than {moved:g} deg": both["answered_a"] & both["answered_b"]
        & ((both["angle_deg_a"] - both["angle_deg_b"]).abs() > moved),
        f"new silent errors (over {silent:g} deg off)": both["answered_a"] & (both["error_a"] > silent)
        & ~(both["answered_b"] & (both["error_b"] > silent)),
        "silent errors gone": both["answered_b"] & (both["error_b"] > silent)
        & ~(both["answered_a"] & (both["error_a"] > silent)),
    }
    for title, sel in groups.items():
        rows = both[sel]
        lines.append(f"{title}: {len(rows)}")
        for idx, r in rows.iterrows():
            if title == "newly refused":
                what = f"was {answer(r, 'b')}; now: {r['reason_a']}"
            elif title == "newly answered":
                what = f"{answer(r, 'a')}, {r['error_a']:.1f} off; was refused: {r['reason_b']}"
            else:
                b = answer(r, "b") if r["answered_b"] else f"refused ({r['reason_b']})"
                a = answer(r, "a") if r["answered_a"] else f"refused ({r['reason_a']})"
                what = f"{b} -> {a}"
            lines.append(row(idx, r, what))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before", help="benchmarks/vision.py --details CSV of the code before the change")
    ap.add_argument("after", help="... and of the code after it (the same seed, suites and options)")
    ap.add_argument("--moved", type=float, default=0.5, help="list answers that moved by more than this (deg)")
    ap.add_argument("--silent", type=float, default=5.0, help="an answer this far off (deg) is a silent error")
    args = ap.parse_args(argv)
    before, after = _read(args.before, ap), _read(args.after, ap)
    print("\n".join(compare(before, after, args.moved, args.silent)))


if __name__ == "__main__":
    sys.exit(main())
