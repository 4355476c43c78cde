"""The Python examples run as a teacher would run them, each writing its figure."""

import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[3]


def run_example(name, *args):
    return subprocess.run(
        [sys.executable, str(ROOT / "examples" / "python" / name), *map(str, args)],
        capture_output=True, text=True, check=False,
    )


def is_png(path):
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_figure6_writes_its_png(tmp_path):
    out = tmp_path / "figure6.png"
    done = run_example("figure6.py", out)
    assert done.returncode == 0, done.stderr
    assert is_png(out)


def test_compare_views_writes_its_png(tmp_path):
    out = tmp_path / "views.png"
    done = run_example("compare_views.py", out, "--size", "256x144", "--resolution", "1024")
    assert done.returncode == 0, done.stderr
    assert is_png(out)


def test_examples_refuse_bad_input_before_any_work(tmp_path):
    for args in (["figure6.py", tmp_path / "f.txt"], ["compare_views.py", tmp_path / "v.png", "--view", "nowhere"],
                 ["compare_views.py", tmp_path / "v.png", "--size", "wide"], ["figure6.py", tmp_path / "f.png", "--zn", "0"]):
        done = run_example(*args)
        assert done.returncode == 2, done.stderr
        assert done.stderr.startswith("error: ") and done.stderr.count("\n") == 1, done.stderr
    assert not list(tmp_path.iterdir())
