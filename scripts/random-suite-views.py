#!/usr/bin/env python3
"""Random views of the scene suite's models (assets/suite: the statues, the engine, the
terrain; fetch them with scripts/fetch-suite.sh --small) for sweeps against the exact shadows:
one suite scene per seed with its objects and ground, and four views with random cameras and
lights (suns at any height, a third of them grazing, 2 to 10 degrees; spots and point lights
over the model), none of them chosen to suit a technique.

    scripts/random-suite-views.py SEED DIR   # writes DIR/scene.toml (meshes by absolute path)
    GENERATOR=scripts/random-suite-views.py scripts/random-sweep.sh FROM TO OUT

The same seed gives the same scene. Needs only Python 3.
"""
import math, os, random, re, sys

if len(sys.argv) != 3 or not sys.argv[1].isdigit():
    print("usage: random-suite-views.py SEED DIR (SEED a whole number)", file=sys.stderr)
    sys.exit(2)
seed, out = int(sys.argv[1]), sys.argv[2]
rng = random.Random(seed)
suite = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "suite"))
name = rng.choice(["statues", "statues", "engine", "engine", "terrain"])
# Each scene's centre of interest, its size and the height of its ground (None: no slab).
center, ext, ground = {
    "statues": ((0, 0.7, 0), 1.6, 0.0),
    "engine": ((0, 1.2, 0), 1.5, 0.0),
    "terrain": ((3840, 300, 3840), 3000, None),
}[name]
models = os.path.join(suite, "models")
if not os.path.isdir(models):
    print(f"random-suite-views.py: {models} is missing (run scripts/fetch-suite.sh --small)",
          file=sys.stderr)
    sys.exit(2)
scene = open(os.path.join(suite, f"{name}.toml")).read()
scene = scene[:scene.index("[[view]]")]
scene = scene.replace('mesh = "models/', f'mesh = "{models}/')
scene = re.sub(r'name = "[a-z_]*"', f'name = "{name}{seed}"', scene, count=1)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


views = []
for k in range(4):
    target = [c + rng.uniform(-ext, ext) * s for c, s in zip(center, (0.8, 0.5, 0.8))]
    away = unit([rng.gauss(0, 1), abs(rng.gauss(0, 0.6)), rng.gauss(0, 1)])
    eye = [t + a * ext * rng.choice([0.5, 1, 2, 4]) for t, a in zip(target, away)]
    if ground is not None:
        eye[1] = max(eye[1], ground + 0.1 * ext / 1.6)
    else:
        eye[1] = max(eye[1], 800.0)  # over the terrain's hills
    near, far = ext / rng.choice([50, 300]), ext * 30
    kind = rng.choice(["sun", "sun", "sun", "spot", "point"])
    if kind == "sun":
        elevation = math.radians(rng.choice([rng.uniform(2, 10), rng.uniform(10, 80)]))
        azimuth = math.radians(rng.uniform(0, 360))
        d = [math.cos(elevation) * math.cos(azimuth), -math.sin(elevation),
             math.cos(elevation) * math.sin(azimuth)]
        light = f"light_dir = [{d[0]:.4f}, {d[1]:.4f}, {d[2]:.4f}]"
    elif kind == "spot":
        p = [c + rng.uniform(-ext, ext) for c in center]
        p[1] = center[1] + ext * rng.uniform(0.8, 2.5)
        d = unit([t - q for t, q in zip(target, p)])
        light = (f"spot = [{p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}, {d[0]:.4f}, {d[1]:.4f}, {d[2]:.4f}, "
                 f"{rng.uniform(20, 70):.1f}, {ext * rng.uniform(4, 10):.2f}]")
    else:
        p = [c + rng.uniform(-ext, ext) for c in center]
        p[1] = center[1] + ext * rng.uniform(0.3, 2)
        light = f"point = [{p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}, {ext * rng.uniform(4, 10):.2f}]"
    views.append(f'[[view]]\nname = "v{k}"\neye = [{eye[0]:.4f}, {eye[1]:.4f}, {eye[2]:.4f}]\n'
                 f'target = [{target[0]:.4f}, {target[1]:.4f}, {target[2]:.4f}]\n'
                 f'fov = {rng.choice([40, 60, 90])}\nnear = {near:.5f}\nfar = {far:.3f}\n{light}\n')
os.makedirs(out, exist_ok=True)
with open(os.path.join(out, "scene.toml"), "w") as f:
    f.write("\n".join([scene] + views))
