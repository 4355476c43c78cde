#!/usr/bin/env bash
# Fetches the real meshes the shadow-volume tests and `gnomon render --mesh` examples use:
# the Stanford bunny (bunny00.off, 75k triangles) and a knot (knot1.off, 6.4k triangles),
# both closed and CC0, from Debian's libcgal-demo package (its
# /usr/share/doc/libcgal-dev/data.tar.gz). They are not committed; they land in
# assets/meshes/ (or in $GNOMON_MESH_DIR when set). Does nothing when they are there.
set -euo pipefail
cd "$(dirname "$0")/.."
dest="${GNOMON_MESH_DIR:-assets/meshes}"
meshes=(bunny00.off knot1.off)

missing=0
for m in "${meshes[@]}"; do
    [ -s "$dest/$m" ] || missing=1
done
if [ "$missing" = 0 ]; then
    echo "fetch-meshes.sh: ${meshes[*]} already in $dest"
    exit 0
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "fetch-meshes.sh: downloading libcgal-demo (about 25 MB) with apt-get download"
if ! (cd "$work" && apt-get download -q libcgal-demo >/dev/null 2>&1); then
    if [ "$(id -u)" = 0 ]; then
        apt-get update -qq
    fi
    (cd "$work" && apt-get download -q libcgal-demo >/dev/null)
fi
dpkg -x "$work"/libcgal-demo_*.deb "$work/root"
mkdir -p "$dest"
tar -xzf "$work/root/usr/share/doc/libcgal-dev/data.tar.gz" -C "$work" \
    "${meshes[@]/#/data/meshes/}"
for m in "${meshes[@]}"; do
    cp "$work/data/meshes/$m" "$dest/$m"
done
echo "fetch-meshes.sh: wrote ${meshes[*]/#/$dest/}"
