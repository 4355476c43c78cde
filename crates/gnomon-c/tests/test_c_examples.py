"""The C and C++ examples, compiled with cc and c++ as a user would, their output checked
against `gnomon setup --json` for the same scene file, view and technique.

Needs target/debug/libgnomon_c.a (cargo build -p gnomon-c) and the command line at
$GNOMON_BIN or target/debug/gnomon.
"""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
LIBRARY = ROOT / "target" / "debug" / "libgnomon_c.a"
SUN_TECHNIQUES = ["uniform", "focused", "psm", "lispsm", "tsm", "xpsm", "sppsm", "cascades"]


def run(*args, cwd=ROOT):
    done = subprocess.run(list(map(str, args)), cwd=cwd, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


@pytest.fixture(scope="module")
def programs(tmp_path_factory):
    assert LIBRARY.exists(), "build the library first: cargo build -p gnomon-c"
    out = tmp_path_factory.mktemp("c")
    include = ROOT / "crates" / "gnomon-c" / "include"
    libs = [LIBRARY, "-lm", "-lpthread", "-ldl"]
    c = out / "shadow_matrices"
    run("cc", "-std=c11", "-Wall", "-Wextra", "-Werror", "-I", include, ROOT / "examples/c/shadow_matrices.c", *libs, "-o", c)
    cpp = out / "frame_loop"
    run("c++", "-std=c++17", "-Wall", "-Wextra", "-Werror", "-I", include, ROOT / "examples/c/frame_loop.cpp", *libs, "-o", cpp)
    return c, cpp


def gnomon_setup(view, technique, *options):
    binary = os.environ.get("GNOMON_BIN") or ROOT / "target" / "debug" / "gnomon"
    return json.loads(
        run(binary, "setup", "--json", "--scene-file", "examples/c/blocks.toml", "--view", view, "--technique", technique, *options)
    )


def assert_maps_equal(ours, theirs):
    assert len(ours) == len(theirs)
    for a, b in zip(ours, theirs):
        assert a["clip_from_world"] == b["clip_from_world"]
        if "depth_from_world" in a:
            assert a["depth_from_world"] == b["depth_from_world"]
        if "resolution" in a:
            assert a["resolution"] == b["resolution"]
        if "view_depth_range" in a:
            assert a["view_depth_range"] == b["view_depth_range"]
        else:
            assert b["view_depth_range"] is None


@pytest.mark.parametrize("view", ["street", "overview"])
@pytest.mark.parametrize("technique", SUN_TECHNIQUES)
def test_c_example_equals_the_command_line(programs, view, technique):
    ours = json.loads(run(programs[0], technique, view))
    theirs = gnomon_setup(view, technique)
    assert ours["fallback"] == theirs["fallback"]
    assert ours["selection"]["kind"] == theirs["selection"]["kind"]
    if ours["selection"]["kind"] == "cascades":
        assert ours["selection"]["view_depths"] == theirs["selection"]["view_depths"]
    assert_maps_equal(ours["maps"], theirs["maps"])


def test_c_example_takes_the_command_lines_options(programs):
    options = "--cascades 3 --cascade-split log --stable"
    ours = json.loads(run(programs[0], "cascades", "street", options))
    assert_maps_equal(ours["maps"], gnomon_setup("street", "cascades", *options.split())["maps"])


def test_c_example_refuses_bad_input_with_one_line(programs):
    for args, message in [
        (["lisp", "street"], "unknown technique 'lisp'"),
        (["focused", "street", "--cascades 3"], "cascades"),
        (["cascades", "street", "--cascades"], "--cascades"),
    ]:
        done = subprocess.run([programs[0], *args], capture_output=True, text=True, check=False)
        assert done.returncode == 2
        assert message in done.stderr and done.stderr.count("\n") == 1, done.stderr


def test_cpp_frame_loop_equals_the_command_line_and_comes_back(programs):
    lines = run(programs[1], "40").splitlines()
    first = json.loads(lines[0])
    assert_maps_equal(first["maps"], gnomon_setup("street", "cascades", "--cascades", "4")["maps"])
    assert len(lines) == 40 and lines[-1].startswith("frame 39: kiosk at x + 0.000")
