#!/usr/bin/env bash
# Makes docs/src/images/stable-vs-best.png, the README's picture: the demo's low_sun view with
# an engine's stable cascades and gnomon's best cascades, the same zoomed part of each, wrong
# pixels against the exact shadow volumes marked (red: false shadow, blue: missed shadow).
# Needs ImageMagick (apt-get install -y imagemagick).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-docs/src/images/stable-vs-best.png}"
dir=$(mktemp -d)
[ -n "${NO_BUILD:-}" ] || cargo build -q --release -p gnomon-cli
target/release/gnomon demo --views low_sun --out "$dir" >/dev/null 2>&1
label() { # IMAGE TEXT OUT: the image at 2.5x, nearest neighbour, with a caption above it
    convert "$1" -scale 250% -background white -gravity north -splice 0x28 \
        -font DejaVu-Sans -pointsize 17 -annotate +0+4 "$2" "$3"
}
wrong() { grep -o "<b>$1</b> · <b>[0-9.]*%" "$dir/index.html" | grep -o "[0-9.]*%"; }
label "$dir/low_sun_cascades-stable_crop_wrong.png" "stable cascades (an engine's): $(wrong cascades-stable) wrong" "$dir/a.png"
label "$dir/low_sun_cascades-best_crop_wrong.png" "gnomon's best cascades: $(wrong cascades-best) wrong" "$dir/b.png"
convert "$dir/a.png" -size 10x1 xc:white "$dir/b.png" -background white +append -strip "$out"
rm -rf "$dir"
echo "wrote $out"
