#!/usr/bin/env bash
# Fetches the models of gnomon's scene suite (assets/suite/*.toml) into assets/suite/models/
# (or $GNOMON_SUITE_DIR/models), from the registries the machines reach. Nothing here is
# committed; the downloads are cached in the models folder's .cache and a model already
# there is not fetched again.
#
#   model                          from                                   licence
#   samurai_monastry.obj (+ .mtl)  PyPI pybullet 3.2.7 (a 103 MB wheel)   zlib (package)
#   2CylinderEngine.glb            Debian assimp-testmodels 5.2.5         CC-BY 4.0 (Khronos)
#   RealisticTerrain.ter           Debian assimp-testmodels 5.2.5         BSD-3 (assimp)
#   armadillo.off                  Debian libcgal-demo 5.5.1              Stanford terms
#   refined_elephant.off           Debian libcgal-demo 5.5.1              CGAL data (LGPL/GPL)
#
# `--small` fetches only the Debian models (about 40 MB of packages), not the wheel.
set -euo pipefail
cd "$(dirname "$0")/.."
dest="${GNOMON_SUITE_DIR:-assets/suite}/models"
cache="$dest/.cache"
mkdir -p "$dest" "$cache"
small=0
[ "${1:-}" = "--small" ] && small=1

deb() { # package: downloads its .deb into the cache once, unpacks it into $cache/$1
    local package="$1"
    if [ ! -d "$cache/$package" ]; then
        if ! ls "$cache"/"${package}"_*.deb >/dev/null 2>&1; then
            echo "fetch-suite.sh: apt-get download $package"
            if ! (cd "$cache" && apt-get download -q "$package" >/dev/null 2>&1); then
                if [ "$(id -u)" = 0 ]; then apt-get update -qq; fi
                (cd "$cache" && apt-get download -q "$package" >/dev/null)
            fi
        fi
        dpkg -x "$cache"/"${package}"_*.deb "$cache/$package"
    fi
}

have() { [ -s "$dest/$1" ]; }

if ! have 2CylinderEngine.glb || ! have RealisticTerrain.ter; then
    deb assimp-testmodels
    models="$cache/assimp-testmodels/usr/share/assimp/models"
    cp "$models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" "$dest/"
    cp "$models/TER/RealisticTerrain.ter" "$dest/"
fi

if ! have armadillo.off || ! have refined_elephant.off; then
    deb libcgal-demo
    tar -xzf "$cache/libcgal-demo/usr/share/doc/libcgal-dev/data.tar.gz" -C "$cache" \
        data/meshes/armadillo.off data/meshes/refined_elephant.off
    cp "$cache/data/meshes/armadillo.off" "$cache/data/meshes/refined_elephant.off" "$dest/"
fi

if [ "$small" = 0 ] && ! have samurai_monastry.obj; then
    if ! ls "$cache"/pybullet-3.2.7-*.whl >/dev/null 2>&1; then
        echo "fetch-suite.sh: pip download pybullet 3.2.7 (about 103 MB)"
        python3 -m pip download -q --no-deps --only-binary=:all: -d "$cache" pybullet==3.2.7
    fi
    python3 - "$cache" "$dest" <<'PY'
import glob, sys, zipfile
cache, dest = sys.argv[1], sys.argv[2]
wheel = sorted(glob.glob(f"{cache}/pybullet-3.2.7-*.whl"))[0]
with zipfile.ZipFile(wheel) as z:
    for name in ("samurai_monastry.obj", "samurai_monastry.mtl"):
        with open(f"{dest}/{name}", "wb") as out:
            out.write(z.read(f"pybullet_data/{name}"))
PY
fi
echo "fetch-suite.sh: models in $dest:"
ls -l "$dest" | grep -v '^total' | grep -v '\.cache'
