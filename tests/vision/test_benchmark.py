import csv
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARK = Path(__file__).resolve().parents[2] / "benchmarks" / "vision.py"


def test_the_benchmark_writes_one_row_per_render_of_every_suite(tmp_path):
    # the renderer's and the drawings' truths have different columns: the details of a
    # run over both must hold every render's row (it failed at the end of a long run)
    out = tmp_path / "results.csv"
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", "2", "--size", "640x480",
                          "--suites", "clean,drawn", "--details", str(out)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [(r["suite"], r["index"]) for r in rows] == [("clean", "0"), ("clean", "1"), ("drawn", "0"), ("drawn", "1")]
    for r in rows:
        assert abs(float(r["true_angle_deg"]) + float(r["error_deg"]) - float(r["angle_deg"])) < 1e-6 \
            or r["angle_deg"] in ("", "nan"), r
    assert rows[0]["skin_tone"] and not rows[2]["skin_tone"]            # the renderer's nuisances
    assert rows[2]["hand_to_finger"] and not rows[0]["hand_to_finger"]  # the drawing's
    # the measurement's own figures: the edges' taper and the knuckle's place on every
    # answer (a refusal has those it got to before it stopped)
    answered = [r for r in rows if r["status"] != "failed"]
    assert answered
    for r in answered:
        assert 0 <= float(r["detail_taper_deg"]) < 12 and 4 < float(r["detail_knuckle_from_tip_widths"]) < 13, r


def _small_clean_run(tmp_path, n, *options):
    """The benchmark over ``n`` small clean renders with ``options``: its output and rows."""
    out = tmp_path / f"results{''.join(options)}.csv"
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", str(n), "--size", "640x480", "--suites", "clean",
                          *options, "--details", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    with open(out, newline="") as fh:
        return run.stdout, list(csv.DictReader(fh))


def test_the_benchmark_puts_the_glove_asked_for_on_every_rendered_finger(tmp_path):
    stdout, rows = _small_clean_run(tmp_path, 2, "--glove", "black")
    assert "clean/black" in stdout
    assert [r["glove"] for r in rows] == ["black", "black"]
    # a drawn suite has no glove to choose: said before anything is run
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", "2", "--glove", "black", "--suites", "clean,drawn"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2 and "--glove" in run.stderr and "drawn" in run.stderr
    assert "clean" not in run.stdout


def test_the_benchmark_gives_every_rendered_hand_a_palm_in_the_range_asked_for(tmp_path):
    stdout, rows = _small_clean_run(tmp_path, 3, "--palm-mm", "6,7")
    assert "clean+palm6-7" in stdout
    palms = [float(r["palm_mm"]) for r in rows]
    assert len(palms) == 3 and all(6 <= p <= 7 for p in palms) and len(set(palms)) == 3
    # the presets' hands have palms of 5-10 mm; 0,0 asks for none
    _, preset = _small_clean_run(tmp_path, 3)
    assert all(5 <= float(r["palm_mm"]) <= 10 for r in preset)
    stdout, without = _small_clean_run(tmp_path, 3, "--palm-mm", "0,0")
    assert "clean+palm0-0" in stdout and [float(r["palm_mm"]) for r in without] == [0, 0, 0]
    # the other nuisances are the preset's own, whatever the palm
    same = ("true_angle_deg", "skin_tone", "roll_deg", "background_bgr", "noise_sigma")
    assert [[r[k] for k in same] for r in rows] == [[r[k] for k in same] for r in preset] \
        == [[r[k] for k in same] for r in without]
    for bad in ("5", "10,5", "a,b"):
        run = subprocess.run([sys.executable, str(BENCHMARK), "--palm-mm", bad], capture_output=True, text=True,
                             timeout=300)
        assert run.returncode == 2 and "--palm-mm" in run.stderr and "5,10" in run.stderr


def test_the_benchmark_puts_tape_bands_on_every_rendered_finger_or_on_none(tmp_path):
    # the realistic preset tapes about half its fingers; --tape on|off tapes all or none,
    # the other nuisances as drawn (what the bands cost is the difference)
    stdout_on, on = _small_clean_run(tmp_path, 3, "--tape", "on")
    stdout_off, off = _small_clean_run(tmp_path, 3, "--tape", "off")
    assert "clean+tape" in stdout_on and "clean-tape" in stdout_off
    assert [r["tape"] for r in on] == ["True"] * 3 and [r["tape"] for r in off] == ["False"] * 3
    same = ("true_angle_deg", "skin_tone", "roll_deg", "background_bgr", "palm_mm")
    assert [[r[k] for k in same] for r in on] == [[r[k] for k in same] for r in off]
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", "2", "--tape", "on", "--suites", "clean,cluttered"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2 and "--tape" in run.stderr and "cluttered" in run.stderr


def _benchmark_module():
    """benchmarks/vision.py as a module (it is a script, not part of the package)."""
    spec = importlib.util.spec_from_file_location("vision_benchmark", BENCHMARK)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_how_alike_the_turns_were_counts_renders_and_spreads():
    # three renders of five photos each: answered in three turns only (spread 2 deg), in
    # none, and in all five alike (spread 0): two of three alike, median spread 1 deg
    nan = float("nan")
    got = [10, 11, 12, nan, nan, nan, nan, nan, nan, nan, 40, 40, 40, 40, 40]
    figures = _benchmark_module().turns_alike(got)
    assert figures["alike"] == pytest.approx(2 / 3) and figures["spread"] == pytest.approx(1.0)


def test_the_benchmark_says_how_alike_the_turns_of_a_render_were_measured(tmp_path):
    # --orientations: five photos per render (as rendered, turned three ways, mirrored);
    # the row ends with the share of renders answered in all five or in none, and the
    # median spread of a render's answers, which the details rows must give too
    stdout, rows = _small_clean_run(tmp_path, 3, "--orientations")
    m = re.search(r"turns: (\d+)% of renders answered alike, median spread ([\d.]+) deg", stdout)
    assert m, stdout
    assert [r["orientation"] for r in rows[:5]] == ["as rendered", "r90", "r180", "r270", "mirror"]
    assert len(rows) == 15 and len({r["true_angle_deg"] for r in rows[:5]}) == 1
    figures = _benchmark_module().turns_alike([float(r["angle_deg"] or "nan") for r in rows])
    assert int(m.group(1)) == round(100 * figures["alike"])
    assert float(m.group(2)) == pytest.approx(figures["spread"], abs=0.006)
    assert 0 < figures["spread"] < 5     # the same bend, measured five times


COMPARE = BENCHMARK.with_name("compare.py")


def test_compare_lists_every_photo_whose_outcome_changed(tmp_path):
    # four photos of one suite: one newly refused, one newly answered, one whose answer
    # moved by 2 deg, one that became a silent error; the fifth is unchanged
    head = "suite,index,image,angle_deg,angle_unc_deg,confidence,status,reason,true_angle_deg\n"
    before = ["realistic,0,a.jpg,30.2,1.0,1.0,ok,,30.0", "realistic,1,b.jpg,,,0.1,failed,too thin,40.0",
              "realistic,2,c.jpg,50.1,1.0,1.0,ok,,50.0", "realistic,3,d.jpg,60.3,1.0,1.0,ok,,60.0",
              "realistic,4,e.jpg,70.4,1.0,1.0,ok,,70.0"]
    after = ["realistic,0,a.jpg,,,0.1,failed,cut short,30.0", "realistic,1,b.jpg,40.3,0.8,0.9,ok,,40.0",
             "realistic,2,c.jpg,52.1,1.0,1.0,ok,,50.0", "realistic,3,d.jpg,67.0,1.0,1.0,ok,,60.0",
             "realistic,4,e.jpg,70.4,1.0,1.0,ok,,70.0"]
    (tmp_path / "before.csv").write_text(head + "\n".join(before) + "\n")
    (tmp_path / "after.csv").write_text(head + "\n".join(after) + "\n")
    run = subprocess.run([sys.executable, str(COMPARE), str(tmp_path / "before.csv"), str(tmp_path / "after.csv")],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    out = run.stdout.splitlines()
    assert out[1].split() == ["realistic", "5", "80.0%", "80.0%", "0", "1"], out
    titles = ("newly answered", "newly refused", "answers moved", "new silent", "silent errors gone")
    listed = {title: [] for title in titles}
    current = None
    for line in out[2:]:
        if not line.startswith("  "):
            current = next(t for t in listed if line.startswith(t))
        else:
            listed[current].append(line.split()[1].rstrip(","))
    assert listed == {"newly answered": ["b.jpg"], "newly refused": ["a.jpg"], "answers moved": ["c.jpg", "d.jpg"],
                      "new silent": ["d.jpg"], "silent errors gone": []}, out
    assert any("a.jpg" in line and "now: cut short" in line for line in out)


def test_compare_names_a_file_that_is_not_a_details_table(tmp_path):
    bad = tmp_path / "angles.csv"
    bad.write_text("image,angle_deg\nx.jpg,3.0\n")
    run = subprocess.run([sys.executable, str(COMPARE), str(bad), str(bad)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    assert str(bad) in run.stderr and "no column suite" in run.stderr and "--details" in run.stderr
