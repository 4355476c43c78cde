"""The Python bindings as their users call them, checked against the command line.

The command line is found at $GNOMON_BIN (scripts/test.sh sets it), else target/debug/gnomon
or target/release/gnomon of this checkout.
"""

import json
import os
import pathlib
import subprocess
import sys
import threading

import numpy as np
import pytest

import gnomon

ROOT = pathlib.Path(__file__).resolve().parents[3]


def gnomon_bin():
    given = os.environ.get("GNOMON_BIN")
    if given:
        return given
    for profile in ("debug", "release"):
        path = ROOT / "target" / profile / "gnomon"
        if path.exists():
            return str(path)
    pytest.fail("no gnomon binary: build it (cargo build -p gnomon-cli) or set GNOMON_BIN")


def cli(*args):
    done = subprocess.run(
        [gnomon_bin(), *args], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def cli_json(*args):
    return json.loads(cli(*args))


POINT_LIGHT = (0.0, 12.0, 5.0, 80.0)


def light_for(technique, view_light):
    """The demo view's sun, or a point light for the techniques that take only those."""
    if technique in ("cube", "paraboloid"):
        return gnomon.Point(POINT_LIGHT[:3], POINT_LIGHT[3]), [
            "--point",
            ",".join(map(str, POINT_LIGHT)),
        ]
    return view_light, []


@pytest.mark.parametrize("technique", gnomon.TECHNIQUES)
def test_every_technique_equals_the_command_line(technique):
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("street")
    light, light_args = light_for(technique, sun)
    ours = json.loads(gnomon.setup(technique, camera, light, scene).to_json())
    theirs = cli_json("setup", "--json", "--view", "street", "--technique", technique, *light_args)
    assert ours == theirs


@pytest.mark.parametrize(
    "params,words",
    [
        (dict(cascades=3, cascade_split="log", stable=True), ["--cascades", "3", "--cascade-split", "log", "--stable"]),
        (dict(cascades=3, cascade_split=[12.5, 40], cascade_fit="tsm"), ["--cascades", "3", "--cascade-split", "12.5,40", "--cascade-fit", "tsm"]),
        (dict(cascades=2, equal_texels=True, cascade_blend=0.2), ["--cascades", "2", "--equal-texels", "--cascade-blend", "0.2"]),
    ],
)
def test_cascade_parameters_equal_the_command_line(params, words):
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("overview")
    ours = gnomon.setup("cascades", camera, sun, scene, resolution=1024, **params)
    theirs = cli_json(
        "setup", "--json", "--view", "overview", "--technique", "cascades", "--shadow-map", "1024", *words
    )
    assert json.loads(ours.to_json()) == theirs
    depths = [m.view_depth_range for m in ours.maps]
    assert all(d is not None and d[0] < d[1] for d in depths)
    assert ours.selection["kind"] == "cascades"


def test_own_camera_and_spot_light_equal_the_command_line():
    scene = gnomon.Scene.demo()
    camera = gnomon.Camera((5, 3, 30), (0, 1, 0), fov=50, aspect=4 / 3, near=0.5, far=150)
    spot = gnomon.Spot((10, 25, 10), (-0.3, -1, -0.3), 35, 120)
    ours = gnomon.setup("lispsm", camera, spot, scene, resolution=512, lispsm_n=8.0)
    theirs = cli_json(
        "setup", "--json", "--technique", "lispsm", "--lispsm-n", "8",
        "--eye", "5,3,30", "--target", "0,1,0", "--fov", "50", "--aspect", str(4 / 3),
        "--near", "0.5", "--far", "150", "--spot", "10,25,10,-0.3,-1,-0.3,35,120",
        "--shadow-map", "512",
    )
    assert json.loads(ours.to_json()) == theirs


def test_maps_are_numpy_and_project_matches_the_matrix():
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("street")
    s = gnomon.setup("cascades", camera, sun, scene)
    assert len(s) == len(s.maps) == 4
    rng = np.random.default_rng(7)
    points = rng.uniform(-30, 30, size=(500, 3))
    for m in s.maps:
        clip = m.clip_from_world
        assert clip.shape == (4, 4) and clip.dtype == np.float64
        assert m.depth_from_world.shape == (4,)
        projected = gnomon.project(m, points)
        assert projected.shape == (500, 3) and projected.dtype == np.float64
        homogeneous = np.c_[points, np.ones(500)] @ clip.T
        np.testing.assert_allclose(projected, homogeneous[:, :3] / homogeneous[:, 3:], rtol=1e-9, atol=1e-9)
        np.testing.assert_array_equal(m.project(points), projected)
    # The JSON's column-major matrix is the array's transpose, flattened.
    first = json.loads(s.to_json())["maps"][0]["clip_from_world"]
    np.testing.assert_array_equal(np.array(first).reshape(4, 4).T, s.maps[0].clip_from_world)


def test_a_perspective_map_gives_nan_behind_its_centre():
    scene = gnomon.Scene.demo()
    camera, _ = scene.view("street")
    s = gnomon.setup("focused", camera, gnomon.Spot((0, 20, 0), (0, -1, 0), 40, 60), scene)
    behind = gnomon.project(s.maps[0], np.array([[0.0, 40.0, 0.0], [0.0, 0.0, 0.0]]))
    assert np.isnan(behind[0]).all() and np.isfinite(behind[1]).all()


def boxes_scene(rng, n):
    centres = rng.uniform(-50, 50, size=(n, 3)) * [1, 0, 1] + [0, 2, 0]
    half = rng.uniform(0.5, 2, size=(n, 3))
    casters = np.stack([centres - half, centres + half], axis=1)
    ground = np.array([[[-60.0, -1, -60], [60, 0, 60]]])
    return casters, ground


def test_box_scenes_take_both_layouts_and_moving_equals_rebuilding():
    rng = np.random.default_rng(1)
    casters, ground = boxes_scene(rng, 200)
    scene = gnomon.Scene(casters, ground)
    flat = gnomon.Scene(casters.reshape(-1, 6), ground.reshape(-1, 6).astype(np.float32))
    np.testing.assert_array_equal(scene.casters, casters)
    assert scene.scene_box.shape == (2, 3) and len(scene) == 201
    camera = gnomon.Camera((0, 20, 80), (0, 0, 0))
    sun = gnomon.Sun((0.3, -1, 0.2))
    assert gnomon.setup("lispsm", camera, sun, scene).to_json() == gnomon.setup("lispsm", camera, sun, flat).to_json()
    shifted = casters + [3.0, 0, -2.0]
    moved = scene.moved(shifted, ground)
    rebuilt = gnomon.Scene(shifted, ground)
    for technique in ("focused", "lispsm", "cascades"):
        a = gnomon.setup(technique, camera, sun, moved)
        b = gnomon.setup(technique, camera, sun, rebuilt)
        for ma, mb in zip(a.maps, b.maps):
            np.testing.assert_allclose(ma.clip_from_world, mb.clip_from_world, rtol=1e-12, atol=1e-12)


def test_own_view_samples_are_read():
    rng = np.random.default_rng(3)
    casters, ground = boxes_scene(rng, 100)
    scene = gnomon.Scene(casters, ground)
    camera = gnomon.Camera((0, 4, 60), (0, 0, 0))
    sun = gnomon.Sun((0.2, -1, 0.6))
    xs, zs = np.meshgrid(np.linspace(-40, 40, 40), np.linspace(-55, 55, 40))
    positions = np.c_[xs.ravel(), np.zeros(xs.size), zs.ravel()]
    normals = np.tile([0.0, 1.0, 0.0], (xs.size, 1))
    with_samples = gnomon.setup("lispsm", camera, sun, scene, samples=(positions, normals))
    assert len(with_samples.maps) == 1
    with pytest.raises(gnomon.GnomonError, match="samples: 1600 positions but 3 normals"):
        gnomon.setup("lispsm", camera, sun, scene, samples=(positions, normals[:3]))
    with pytest.raises(gnomon.GnomonError, match=r"samples\[1\] \(normals\): expected shape \(N, 3\)"):
        gnomon.setup("lispsm", camera, sun, scene, samples=(positions, normals[:, :2]))


def test_bad_input_raises_one_line_errors_naming_the_argument():
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("street")
    cases = [
        (lambda: gnomon.setup("lisp", camera, sun, scene), "unknown technique 'lisp'"),
        (lambda: gnomon.setup("focused", camera, sun, scene, cascades=3), "cascades"),
        (lambda: gnomon.setup("cascades", camera, sun, scene, cascade=3), "unknown parameter 'cascade'"),
        (lambda: gnomon.setup("cascades", camera, sun, scene, stable=3), "stable is True or False"),
        (lambda: gnomon.setup("focused", camera, sun, scene, resolution=0), "resolution: 0"),
        (lambda: gnomon.setup("focused", camera, "sun", scene), "light: expected a gnomon.Sun"),
        (lambda: gnomon.Scene(np.zeros((3, 3)), np.zeros((0, 6))), r"casters: expected shape \(N, 2, 3\) or \(N, 6\)"),
        (lambda: gnomon.Scene(np.zeros((1, 6), dtype=np.int64), np.zeros((0, 6))), "casters: expected float64 or float32 values, got dtype int64"),
        (lambda: gnomon.Scene(np.array([[1.0, 0, 0, 0, 1, 1]]), np.zeros((0, 6))), r"casters\[0\]"),
        (lambda: gnomon.Scene(np.zeros((0, 6)), []), "scene"),
        (lambda: gnomon.Scene([["a"]], []), "casters: expected an array of numbers"),
        (lambda: gnomon.Camera((0, 0, 0), (0, 0, 0)), "eye equals target"),
        (lambda: gnomon.Camera((0, 0, 0), (0, 0, 1), near=5, far=2), "0 < near < far"),
        (lambda: gnomon.Camera((0, 0), (0, 0, 1)), r"eye: expected 3 numbers"),
        (lambda: gnomon.Sun((0, 0, 0)), "zero length"),
        (lambda: gnomon.Sun((0, float("nan"), 1)), "not a finite number"),
        (lambda: gnomon.Spot((0, 5, 0), (0, -1, 0), 120, 10), r"half-angle must be in \(0, 89\]"),
        (lambda: gnomon.Point((0, 5, 0), -1), "range must be positive"),
        (lambda: scene.view("nowhere"), "unknown view 'nowhere'"),
        (lambda: gnomon.Scene.builtin("atlantis"), "unknown scene 'atlantis'"),
        (lambda: gnomon.Scene.load("no/such/file.obj"), "no/such/file.obj"),
        (lambda: gnomon.analyze(zn=5, zf=2), "0 < near < far"),
        (lambda: gnomon.project(gnomon.setup("focused", camera, sun, scene).maps[0], np.zeros(3)), r"points: expected shape \(N, 3\)"),
    ]
    for call, message in cases:
        with pytest.raises(gnomon.GnomonError, match=message) as caught:
            call()
        text = str(caught.value)
        assert text and "\n" not in text, text
        assert isinstance(caught.value, ValueError)


def test_analyze_equals_the_command_line_and_has_the_papers_curves():
    ours = gnomon.analyze(zn=1, zf=100, gamma=90, samples=50)
    theirs = cli_json("analyze", "--json", "--zn", "1", "--zf", "100", "--gamma", "90", "--samples", "50")
    assert json.loads(ours.to_json()) == theirs
    z, dp_ds = ours.curve("lispsm")
    assert z.shape == dp_ds.shape == (50,)
    assert z[0] == pytest.approx(1) and z[-1] == pytest.approx(100)
    # The LiSPSM paper's Figure 6: LiSPSM's worst aliasing lies between the logarithmic
    # limit and the uniform map's.
    uniform = ours.curve("uniform")[1].max()
    assert ours.logarithmic_ideal < dp_ds.max() < uniform
    rows = {r["technique"]: r for r in ours.rows}
    assert {"uniform", "psm-paper", "lispsm"} <= set(rows)
    np.testing.assert_array_equal(rows["lispsm"]["dp_ds"], dp_ds)


def test_help_says_what_setup_takes():
    doc = gnomon.setup.__doc__
    assert "samples" in doc and "GnomonError" in doc and "cascade_split" in doc
    assert "resolution=2048" in gnomon.setup.__text_signature__
    assert gnomon.Scene.__doc__ and gnomon.Map.clip_from_world.__doc__


def test_setups_run_in_threads_without_the_gil():
    rng = np.random.default_rng(5)
    casters, ground = boxes_scene(rng, 2000)
    scene = gnomon.Scene(casters, ground)
    camera = gnomon.Camera((0, 3, 70), (0, 2, 0))
    sun = gnomon.Sun((0.3, -1, 0.2))
    expected = gnomon.setup("cascades", camera, sun, scene).to_json()
    results = []
    threads = [
        threading.Thread(target=lambda: results.append(gnomon.setup("cascades", camera, sun, scene).to_json()))
        for _ in range(4)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == [expected] * 4


def read_png(path):
    from PIL import Image

    return np.asarray(Image.open(path))


@pytest.mark.parametrize("technique", ["lispsm", "cascades", "volumes"])
def test_render_mask_equals_the_command_line(tmp_path, technique):
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("street", aspect=320 / 180)
    frame = gnomon.render(scene, camera, sun, technique=technique, size=(320, 180), resolution=1024)
    assert frame.frame.shape == (180, 320, 3) and frame.frame.dtype == np.uint8
    assert frame.mask.shape == (180, 320) and frame.mask.dtype == np.uint8
    assert set(np.unique(frame.mask)) <= {0, 128, 255}
    assert (frame.mask == 0).mean() > 0.01 and (frame.mask == 255).mean() > 0.05
    mask = tmp_path / "mask.png"
    cli(
        "render", "--view", "street", "--technique", technique, "--size", "320x180",
        "--shadow-map", "1024", "--out", str(tmp_path / "frame.png"), "--mask", str(mask),
    )
    np.testing.assert_array_equal(frame.mask, read_png(mask))
    if technique == "volumes":
        assert frame.error_map is None and frame.setup is None
    else:
        error = frame.error_map
        assert error.shape == (180, 320) and error.dtype == np.float32
        assert (error[frame.mask != 128] != 0).mean() > 0.9
        assert frame.setup.technique == technique


def test_render_of_boxes_and_its_refusals():
    rng = np.random.default_rng(2)
    casters, ground = boxes_scene(rng, 40)
    scene = gnomon.Scene(casters, ground)
    camera = gnomon.Camera((0, 25, 70), (0, 0, 0), aspect=2.0)
    sun = gnomon.Sun((0.4, -1, 0.3))
    exact = gnomon.render(scene, camera, sun, technique="volumes", size=(256, 128))
    mapped = gnomon.render(scene, camera, sun, technique="lispsm", size=(256, 128))
    geometry = exact.mask != 128
    assert geometry.mean() > 0.5 and (exact.mask == 0).mean() > 0.02
    np.testing.assert_array_equal(mapped.mask != 128, geometry)
    assert (mapped.mask[geometry] != exact.mask[geometry]).mean() < 0.02
    with pytest.raises(gnomon.GnomonError, match="aspect"):
        gnomon.render(scene, camera, sun, size=(256, 256))
    with pytest.raises(gnomon.GnomonError, match="size"):
        gnomon.render(scene, camera, sun, size=(0, 128))
    with pytest.raises(gnomon.GnomonError, match="volumes take no technique parameters"):
        gnomon.render(scene, camera, sun, technique="volumes", size=(256, 128), cascades=2)
    loaded = gnomon.Scene.demo()
    moved = loaded.moved(loaded.casters + [0, 1, 0], loaded.receivers)
    with pytest.raises(gnomon.GnomonError, match="meshes cannot follow"):
        gnomon.render(moved, *loaded.view("street"))


def test_the_readme_example_prints_what_the_readme_says():
    text = (ROOT / "README.md").read_text()
    section = text.split("## From Python", 1)[1].split("\n## ", 1)[0]
    command = next(line for line in section.splitlines() if line.startswith('python -c "'))
    code = command[len('python -c "'):-1]
    expected = section.split("```text\n", 1)[1].split("```", 1)[0]
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout == expected


def test_compare_rows_equal_the_command_lines_report(tmp_path):
    scene = gnomon.Scene.demo()
    camera, sun = scene.view("low_sun", aspect=320 / 180)
    rows = gnomon.compare(scene, camera, sun, techniques=["focused", "lispsm", "cascades"], size=(320, 180), resolution=1024)
    cli(
        "compare", "--views", "low_sun", "--techniques", "focused,lispsm,cascades", "--size", "320x180",
        "--shadow-map", "1024", "--out", str(tmp_path),
    )
    report = json.loads((tmp_path / "report.json").read_text())
    theirs = {r["technique"]: r for r in report["views"][0]["techniques"]}
    assert [r["technique"] for r in rows] == ["focused", "lispsm", "cascades"]
    for row in rows:
        expected = theirs[row["technique"]]
        for key in ("maps", "fallback", "wrong_percent", "false_shadow_percent", "missed_shadow_percent",
                    "compared_pixels", "unsure_percent", "sure_wrong_percent", "undersampling",
                    "area_undersampling", "shadow_map"):
            assert row[key] == expected[key], key
        assert row["setup_us"] > 0 and row["frame_ms"] > 0
    assert rows[0]["wrong_percent"] > rows[2]["wrong_percent"]
    with pytest.raises(gnomon.GnomonError, match="unknown technique 'volume'"):
        gnomon.compare(scene, camera, sun, techniques=["volume"], size=(320, 180))
    with pytest.raises(gnomon.GnomonError, match="--stable"):
        gnomon.compare(scene, camera, sun, techniques=["focused"], size=(320, 180), stable=True)


@pytest.mark.parametrize(
    "load,words,view",
    [
        (lambda: gnomon.Scene.load(ROOT / "examples/c/blocks.toml"), ["--scene-file", "examples/c/blocks.toml"], "street"),
        (lambda: gnomon.Scene.load(str(ROOT / "assets/scenes/block.off"), mesh_height=5), ["--mesh", "assets/scenes/block.off", "--mesh-height", "5"], "oblique"),
        (lambda: gnomon.Scene.builtin("city"), ["--scene", "city"], None),
    ],
)
def test_loaded_scenes_equal_the_command_line(load, words, view):
    scene = load()
    view = view or scene.views[0]
    camera, light = scene.view(view)
    ours = gnomon.setup("lispsm", camera, light, scene)
    theirs = cli_json("setup", "--json", *words, "--view", view, "--technique", "lispsm")
    assert json.loads(ours.to_json()) == theirs
