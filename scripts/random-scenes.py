#!/usr/bin/env python3
"""Random scene files for sweeps against the exact shadows: boxes (some rotated, some floating,
some thin plates in the air) and spheres on a ground, and four views with random cameras and
lights (suns at any height, grazing ones and ones along or against the view drawn on purpose;
spots; point lights), none of them chosen to suit a technique.

    scripts/random-scenes.py SEED DIR      # writes DIR/scene.toml, DIR/block.off, DIR/ball.off
    cargo run --release -p gnomon-cli -- compare --scene-file DIR/scene.toml \
        --techniques all --size 320x180 --shadow-map 1024 --out DIR/out

The same seed gives the same scene. Needs only Python 3.
"""
import math, os, random, sys

if len(sys.argv) != 3 or not sys.argv[1].isdigit():
    print("usage: random-scenes.py SEED DIR (SEED a whole number)", file=sys.stderr)
    sys.exit(2)
seed = int(sys.argv[1]); out = sys.argv[2]
rng = random.Random(seed)
os.makedirs(out, exist_ok=True)
# meshes
here = os.path.dirname(os.path.abspath(__file__))
open(f"{out}/block.off", "w").write(open(os.path.join(here, "..", "assets", "scenes", "block.off")).read())
def icosphere(path, sub=2):
    t=(1+5**0.5)/2
    v=[(-1,t,0),(1,t,0),(-1,-t,0),(1,-t,0),(0,-1,t),(0,1,t),(0,-1,-t),(0,1,-t),(t,0,-1),(t,0,1),(-t,0,-1),(-t,0,1)]
    v=[tuple(c/math.sqrt(sum(x*x for x in p)) for c in p) for p in v]
    f=[(0,11,5),(0,5,1),(0,1,7),(0,7,10),(0,10,11),(1,5,9),(5,11,4),(11,10,2),(10,7,6),(7,1,8),(3,9,4),(3,4,2),(3,2,6),(3,6,8),(3,8,9),(4,9,5),(2,4,11),(6,2,10),(8,6,7),(9,8,1)]
    for _ in range(sub):
        cache={}; nf=[]
        def mid(a,b):
            k=(min(a,b),max(a,b))
            if k not in cache:
                p=[(v[a][i]+v[b][i])/2 for i in range(3)]; l=math.sqrt(sum(x*x for x in p))
                v.append(tuple(x/l for x in p)); cache[k]=len(v)-1
            return cache[k]
        for a,b,c in f:
            ab,bc,ca=mid(a,b),mid(b,c),mid(c,a)
            nf+= [(a,ab,ca),(b,bc,ab),(c,ca,bc),(ab,bc,ca)]
        f=nf
    with open(path,"w") as o:
        o.write(f"OFF\n{len(v)} {len(f)} 0\n")
        for p in v: o.write(f"{p[0]*0.5:.6f} {p[1]*0.5+0.5:.6f} {p[2]*0.5:.6f}\n")
        for a,b,c in f: o.write(f"3 {a} {b} {c}\n")
icosphere(f"{out}/ball.off")
L = []
size = rng.choice([80, 150, 300])
L.append(f'name = "sweep{seed}"\n[ground]\nsize = {size}\n')
n = rng.randint(6, 30)
h = size*0.35
for i in range(n):
    mesh = rng.choice(["block.off"]*3 + ["ball.off"])
    sx, sy, sz = rng.uniform(1, 20), rng.uniform(0.5, 30), rng.uniform(1, 20)
    if mesh == "ball.off":
        s = rng.uniform(2, 12); sx=sy=sz=s
    y = 0.0 if rng.random() < 0.7 else rng.uniform(1, 15)   # some float above the ground
    if rng.random() < 0.1: sy = rng.uniform(0.2, 0.6); y = rng.uniform(3, 10)  # thin plates in the air
    L.append(f'[[object]]\nmesh = "{mesh}"\ntranslate = [{rng.uniform(-h,h):.3f}, {y:.3f}, {rng.uniform(-h,h):.3f}]\n'
             f'scale = [{sx:.3f}, {sy:.3f}, {sz:.3f}]\nrotate_y_degrees = {rng.uniform(0,90):.2f}\n')
for k in range(4):
    kind = rng.choice(["sun","sun","sun","spot","point"])
    eh = rng.choice([1.7, 5, 20, 60, 150])
    r = rng.uniform(0.2, 1.0)*size*0.6
    a = rng.uniform(0, 2*math.pi)
    eye = [r*math.cos(a), eh, r*math.sin(a)]
    tgt = [rng.uniform(-h,h)*0.5, rng.uniform(0, 8), rng.uniform(-h,h)*0.5]
    far = rng.choice([100, 300, 600])
    near = rng.choice([0.1, 0.5, 1.0])
    fov = rng.choice([30, 60, 90])
    v = f'[[view]]\nname = "v{k}"\neye = [{eye[0]:.3f}, {eye[1]:.3f}, {eye[2]:.3f}]\ntarget = [{tgt[0]:.3f}, {tgt[1]:.3f}, {tgt[2]:.3f}]\nfov = {fov}\nnear = {near}\nfar = {far}\n'
    if kind == "sun":
        el = rng.choice([rng.uniform(2, 15), rng.uniform(15, 89.9)])  # grazing suns drawn on purpose
        if rng.random() < 0.25:   # light along/against the view direction
            d = [tgt[i]-eye[i] for i in range(3)]
            s = rng.choice([1, -1]); d = [s*x for x in d]; d[1] = -abs(d[1]) - 0.05
        else:
            az = rng.uniform(0, 2*math.pi); e = math.radians(el)
            d = [math.cos(e)*math.cos(az), -math.sin(e), math.cos(e)*math.sin(az)]
        v += f'light_dir = [{d[0]:.4f}, {d[1]:.4f}, {d[2]:.4f}]\n'
    elif kind == "spot":
        p = [rng.uniform(-h,h)*0.5, rng.uniform(8, 40), rng.uniform(-h,h)*0.5]
        d = [rng.uniform(-0.6,0.6), -1, rng.uniform(-0.6,0.6)]
        v += f'spot = [{p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}, {d[0]:.3f}, {d[1]:.3f}, {d[2]:.3f}, {rng.uniform(20,70):.1f}, {rng.uniform(40,200):.1f}]\n'
    else:
        p = [rng.uniform(-h,h)*0.5, rng.uniform(2, 20), rng.uniform(-h,h)*0.5]
        v += f'point = [{p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}, {rng.uniform(30,200):.1f}]\n'
    L.append(v)
open(f"{out}/scene.toml","w").write("\n".join(L))
