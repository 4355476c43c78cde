#!/usr/bin/env python3
"""Random gnomon command lines, the hard cases drawn on purpose (the light along or against the
view, the eye inside a box or on the ground, tiny and huge near and far planes, extreme fields
of view, spots and point lights inside objects, every technique and cascade option, now and
then a value out of range or an option the technique does not take).

    scripts/fuzz.py setup SEED COUNT [GNOMON]
        `gnomon setup --json`: each run either prints a setup whose every number is finite
        (exit 0) or one line of error (exit 2), never a panic, a NaN, another exit code or a
        hang. About 50 command lines a second.
    scripts/fuzz.py render SEED COUNT [GNOMON]
        `gnomon render --mask` at 160x90 with maps of 512 to 2048 texels (no --shadow-distance)
        and the exact shadow volumes' mask of the same view and light: the same exit rules,
        and the two may differ (in the mask and visibly in colour) on at most 5% of the pixels
        (a shadow lost or a map gone wrong, not a texel's aliasing), unless the render warns that a caster within the
        light's near distance casts no shadow in the maps. About 2 s a command line on
        lavapipe. (A camera inside a closed object sees the inside of its faces; there the
        maps and the volumes can disagree on whole edges: such failures want a look, not a
        fix.)

GNOMON defaults to target/release/gnomon. Prints each failing command line and exits 1 if there
was one. The same seed gives the same command lines. Needs Python 3 (and for `render`, a GPU
adapter or Mesa's lavapipe; the masks are decoded with the standard library).
"""
import json, math, os, random, shutil, subprocess, sys, tempfile

if (len(sys.argv) not in (4, 5) or sys.argv[1] not in ("setup", "render")
        or not sys.argv[2].isdigit() or not sys.argv[3].isdigit()):
    print("usage: fuzz.py setup|render SEED COUNT [GNOMON] (SEED and COUNT whole numbers)",
          file=sys.stderr)
    sys.exit(2)
mode, seed, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
here = os.path.dirname(os.path.abspath(__file__))
gnomon = sys.argv[4] if len(sys.argv) == 5 else os.path.join(here, "..", "target", "release", "gnomon")
rng = random.Random(seed)
TECHNIQUES = ["uniform", "focused", "psm", "lispsm", "tsm", "xpsm", "sppsm", "cascades", "cube",
              "paraboloid"]


def vec(v):
    return ",".join(f"{x:.9g}" for x in v)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else v


def rand_dir():
    return unit([rng.gauss(0, 1) for _ in range(3)])


def nudge(d, eps):
    return unit([x + rng.gauss(0, eps) for x in d])


def command(map_sizes, shadow_distance, on_surfaces):
    """(the scene, view and light options, the technique's options), maps within `map_sizes`;
    with `on_surfaces`, eyes and lamps also exactly on the ground's top or inside the ground
    (views whose pictures are ill-posed: fine for setups, not for comparing pictures)."""
    args = ["--scene", rng.choice(["demo", "demo", "demo", "city"])]
    scale = 600 if args[-1] == "city" else 120
    # camera
    eye = [rng.uniform(-scale, scale), rng.choice([rng.uniform(0, 3), rng.uniform(0, scale / 2),
           ] + ([0.0, -1.0] if on_surfaces else [])), rng.uniform(-scale, scale)]
    if rng.random() < 0.3:  # look down a near-vertical axis, or at the eye's own height
        fwd = nudge([0, rng.choice([-1, 1]), 0], rng.choice([0, 1e-7, 1e-3, 1e-3, 0.1, 0.1]))
    else:
        fwd = rand_dir()
    dist = rng.choice([1e-3, 1, 30, 300])
    target = [e + f * dist for e, f in zip(eye, fwd)]
    args += ["--eye", vec(eye), "--target", vec(target)]
    if rng.random() < 0.2:
        args += ["--up", vec(rng.choice([fwd, rand_dir(), [0, 1, 0]]))]
    if rng.random() < 0.4:
        args += ["--fov", f"{rng.choice([0.5, 10, 60, 120, 170, 179.5]):g}"]
    near = rng.choice([None, 1e-4, 0.01, 1, 50])
    far = rng.choice([None, 2, 100, 1e4, 1e6])
    if near is not None:
        args += ["--near", f"{near:g}"]
    if far is not None:
        args += ["--far", f"{far:g}"]
    if rng.random() < 0.2:
        args += ["--aspect", f"{rng.choice([0.1, 1, 1.78, 8]):g}"]
    # light
    kind = rng.choice(["sun", "sun", "sun", "spot", "point"])
    if kind == "sun":
        d = rng.choice([rand_dir(), nudge(fwd, rng.choice([0, 1e-6, 1e-3, 0.05])),
                        nudge([-x for x in fwd], rng.choice([0, 1e-6, 1e-3, 0.05])),
                        unit([rng.gauss(0, 1), -rng.uniform(0, 0.05), rng.gauss(0, 1)]),
                        [0, -1, 0]])
        args += ["--light-dir", vec(d)]
    elif kind == "spot":
        p = rng.choice([[rng.uniform(-scale, scale), rng.uniform(0, scale / 2), rng.uniform(-scale, scale)],
                        eye if eye[1] > 0 or on_surfaces else [0, 2, 0], [0, 2, 0]])
        d = rng.choice([rand_dir(), fwd, [0, -1, 0]])
        half = rng.choice([1, 30, 60, 89, 89.9])
        rng_ = rng.choice([1, 50, 1000, 1e5])
        args += ["--spot", vec(p + d + [half, rng_])]
    else:
        p = rng.choice([[rng.uniform(-scale, scale), rng.uniform(0, scale / 2), rng.uniform(-scale, scale)],
                        eye if eye[1] > 0 or on_surfaces else [0, 2, 0], [0, 2, 0]]
                       + ([[0, 0, 0]] if on_surfaces else []))
        args += ["--point", vec(p + [rng.choice([1, 50, 1000, 1e5])])]
    # the technique for the light (now and then any, for the errors)
    if rng.random() < 0.05:
        technique = rng.choice(TECHNIQUES)
    elif kind == "point":
        technique = rng.choice(["cube", "paraboloid", "focused", "lispsm", "uniform"])
    elif kind == "spot":
        technique = rng.choice(["uniform", "focused", "psm", "lispsm", "tsm", "xpsm", "sppsm", "cascades"])
    else:
        technique = rng.choice(["uniform", "focused", "psm", "lispsm", "tsm", "xpsm", "sppsm",
                                "cascades", "cascades"])
    scene_view_light, args = args, ["--technique", technique]
    wild = rng.random() < 0.05  # options the technique does not take
    if rng.random() < 0.5:
        sizes = [n for n in [8, 16, 512, 2048, 16384] if map_sizes[0] <= n <= map_sizes[1]]
        sizes += [1] if wild else []
        args += ["--shadow-map", str(rng.choice(sizes))]
    if technique == "cascades" or wild:
        args += ["--cascades", str(rng.choice([1, 2, 4, 8]))]
        args += ["--cascade-split", rng.choice(["practical", "log", "uniform", "first-log:10",
                                                "first-log:1000", "5,20,80", "1e-3"])]
        stable = rng.random() < 0.3 and kind == "sun"
        if stable:
            args += ["--stable"]
        if rng.random() < 0.5 and (not stable or wild):
            args += ["--cascade-fit", rng.choice(["focused", "lispsm", "tsm", "xpsm", "psm"])]
        if rng.random() < 0.3:
            args += ["--equal-texels"]
        if shadow_distance and rng.random() < 0.3:
            args += ["--shadow-distance", f"{rng.choice([0.5, 10, 1e3, 1e7]):g}"]
        if rng.random() < 0.3:
            args += ["--cascade-blend", f"{rng.choice([0, 0.25, 0.5]):g}"]
        if rng.random() < 0.3:
            # with split distances: refused (one line, exit 2)
            args += ["--cascade-adaptive"]
        if rng.random() < 0.3:
            # coverage needs --stable: refused (one line, exit 2) without it
            args += ["--cascade-select", rng.choice(["auto", "depth", "coverage"])]
    if technique == "sppsm" and rng.random() < 0.5 or wild:
        args += ["--sppsm-with", rng.choice(["psm", "lispsm", "tsm", "xpsm"])]
    warped = technique in ("psm", "lispsm", "tsm", "xpsm", "cascades")
    if (warped or wild) and rng.random() < 0.15:
        args += ["--no-warp-limit"]
    if (technique in ("lispsm", "cascades") or wild) and rng.random() < 0.1:
        args += ["--lispsm-n", f"{rng.choice([1e-6, 1, 1e6]):g}"]
    return scene_view_light, args


def finite(x):
    if isinstance(x, float):
        return math.isfinite(x)
    if isinstance(x, dict):
        return all(finite(v) for v in x.values())
    if isinstance(x, list):
        return all(finite(v) for v in x)
    return True


def read_png(path):
    """An 8-bit, non-interlaced PNG: rows of pixels, each a tuple of its channels."""
    import struct, zlib
    data = open(path, "rb").read()
    pos, idat, width, height, channels = 8, b"", 0, 0, 1
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and body[12] == 0, "8-bit, non-interlaced PNG expected"
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[i:i + channels]) for i in range(0, stride, channels)])
        prev = line
    return rows


def exit_problem(run):
    """What is wrong with how a command ended, or None."""
    err = run.stderr.strip()
    if "panicked" in run.stderr or run.returncode not in (0, 2):
        return f"exit {run.returncode}: {err[-400:]}"
    if run.returncode == 2 and (not err or len(err.splitlines()) != 1):
        return f"exit 2 without one line of error: {err[-400:]!r}"
    return None


def run(args):
    try:
        return subprocess.run([gnomon] + args, capture_output=True, text=True, timeout=120), None
    except subprocess.TimeoutExpired:
        return None, "no answer within 120 s"


def check_setup(scene_view_light, technique):
    args = ["setup", "--json"] + scene_view_light + technique
    done, problem = run(args)
    problem = problem or exit_problem(done)
    if problem or done.returncode != 0:
        return args, problem
    try:
        out = json.loads(done.stdout)
    except ValueError as e:
        return args, f"output is not JSON ({e})"
    if not finite(out):
        return args, "a number in the setup is not finite"
    if not out.get("maps"):
        return args, "no maps in the setup"
    return args, None


def check_render(scene_view_light, technique, work):
    size = ["--size", "160x90"]
    args = ["render"] + scene_view_light + technique + size + [
        "--out", f"{work}/frame.png", "--mask", f"{work}/mask.png"]
    done, problem = run(args)
    problem = problem or exit_problem(done)
    if problem or done.returncode != 0:
        return args, problem
    warnings = done.stderr
    exact = ["render"] + scene_view_light + ["--technique", "volumes"] + size + [
        "--out", f"{work}/exact.png", "--mask", f"{work}/exact_mask.png"]
    done, problem = run(exact)
    problem = problem or exit_problem(done)
    if problem or done.returncode != 0:
        return args, problem or f"the exact volumes failed: {done.stderr.strip()[-300:]}"
    if "the exact volumes keep it" in warnings:
        return args, None  # a caster within the light's near distance: the maps drop it
    # A pixel differs where the masks do and the colours too: a lit or shadowed surface
    # nearly edge-on to the light (N.L near 0) looks the same either way, and such pixels
    # flip on roundings.
    masks = read_png(f"{work}/mask.png"), read_png(f"{work}/exact_mask.png")
    frames = read_png(f"{work}/frame.png"), read_png(f"{work}/exact.png")
    pixels = sum(len(row) for row in masks[0])
    differ = sum(abs(m[0] - n[0]) > 64 and max(abs(x - y) for x, y in zip(c[:3], d[:3])) > 12
                 for rm, rn, rc, rd in zip(*masks, *frames)
                 for m, n, c, d in zip(rm, rn, rc, rd))
    if differ > 0.05 * pixels:
        return args, f"the picture differs from the exact volumes' on {100 * differ / pixels:.1f}% of the pixels"
    return args, None


failures = 0
work = tempfile.mkdtemp(prefix="gnomon-fuzz-")
for i in range(count):
    if mode == "setup":
        args, problem = check_setup(*command((1, 16384), shadow_distance=True, on_surfaces=True))
    else:
        args, problem = check_render(*command((512, 2048), shadow_distance=False, on_surfaces=False), work)
    if problem:
        failures += 1
        print(f"FAIL {i}: gnomon {' '.join(args)}\n    {problem}", flush=True)
    elif mode == "render" and (i + 1) % 10 == 0:
        print(f"fuzz.py: {i + 1} of {count}", file=sys.stderr, flush=True)
shutil.rmtree(work, ignore_errors=True)
print(f"fuzz.py: {count} {mode} command lines, {failures} failing", file=sys.stderr)
sys.exit(1 if failures else 0)
