import csv
import subprocess
import sys
from pathlib import Path

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


def test_the_benchmark_puts_the_glove_asked_for_on_every_rendered_finger(tmp_path):
    out = tmp_path / "results.csv"
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", "2", "--size", "640x480", "--suites", "clean",
                          "--glove", "black", "--details", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "clean/black" in run.stdout
    with open(out, newline="") as fh:
        assert [r["glove"] for r in csv.DictReader(fh)] == ["black", "black"]
    # a drawn suite has no glove to choose: said before anything is run
    run = subprocess.run([sys.executable, str(BENCHMARK), "--n", "2", "--glove", "black", "--suites", "clean,drawn"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 2 and "--glove" in run.stderr and "drawn" in run.stderr
    assert "clean" not in run.stdout
