"""The Python bindings' cost over the Rust core, measured in one run on one machine: a
4-cascade setup at 10^3 boxes (criterion's setup/cascades_4_lispsm_directional/1000) and a
Scene from 10^4 boxes (criterion's scale/bounds_and_hierarchies/10000), on the same city of
boxes as crates/gnomon/benches/common/city.rs.

    bash scripts/python-overhead.sh      (runs the two criterion benches, then this)
"""

import json
import pathlib
import statistics
import sys
import timeit

import numpy as np

import gnomon

ROOT = pathlib.Path(__file__).resolve().parents[1]


def city(n):
    """benches/common/city.rs's city(n, true): the same floating-point operations."""
    side = int(np.ceil(np.sqrt(n)))
    pitch = 380.0 / side
    k = np.arange(n)
    i, j = (k % side).astype(float), (k // side).astype(float)
    h = 2.0 + ((k * 7919) % 38).astype(float)
    lo = np.stack([-190.0 + i * pitch, np.zeros(n), -190.0 + j * pitch], axis=1)
    hi = lo + np.stack([np.full(n, 0.6 * pitch), h, np.full(n, 0.6 * pitch)], axis=1)
    boxes = np.stack([lo, hi], axis=1)
    ground = np.array([[[-200.0, -1.0, -200.0], [200.0, 0.0, 200.0]]])
    return boxes, np.concatenate([boxes, ground])


def criterion_median_us(group, name, n):
    path = ROOT / "target" / "criterion" / group / name / str(n) / "new" / "estimates.json"
    if not path.exists():
        sys.exit(f"error: {path} is missing: run scripts/python-overhead.sh")
    return json.loads(path.read_text())["median"]["point_estimate"] / 1000.0


def python_median_us(call, number):
    runs = timeit.repeat(call, number=number, repeat=15)
    return statistics.median(runs) / number * 1e6


def main():
    camera = gnomon.Camera((-150, 30, 180), (20, 0, -20))
    sun = gnomon.Sun((0.5, -1.0, -0.3))
    casters, receivers = city(1000)
    scene = gnomon.Scene(casters, receivers)
    setup_py = python_median_us(lambda: gnomon.setup("cascades", camera, sun, scene), 200)
    setup_rs = criterion_median_us("setup", "cascades_4_lispsm_directional", 1000)
    big_casters, big_receivers = city(10_000)
    scene_py = python_median_us(lambda: gnomon.Scene(big_casters, big_receivers), 20)
    scene_rs = criterion_median_us("scale", "bounds_and_hierarchies", 10_000)
    print(f"4-cascade setup, 10^3 boxes: Python {setup_py:.1f} us, Rust {setup_rs:.1f} us, "
          f"ratio {setup_py / setup_rs:.3f} (at most 1.3)")
    print(f"Scene from 10^4 boxes: Python {scene_py:.1f} us, Rust {scene_rs:.1f} us, "
          f"ratio {scene_py / scene_rs:.3f} (at most 1.2)")


if __name__ == "__main__":
    main()
