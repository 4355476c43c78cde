#!/usr/bin/env bash
# Makes docs/src/images/viewer.png, the book's picture of `gnomon view`: the viewer with its panel in
# a 1280x720 Xvfb screen, captured by ImageMagick (apt-get install -y xvfb xauth imagemagick).
# Usage: bash scripts/viewer-screenshot.sh [OUT.png] [gnomon view options...]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-docs/src/images/viewer.png}"
shift || true
cargo build --release -p gnomon-cli --features viewer
options=("$@")
[ "${#options[@]}" = 0 ] && options=(--view overview --technique lispsm --split focused)
inner=$(mktemp)
cat > "$inner" <<INNER
#!/bin/sh
"$PWD/target/release/gnomon" view --size 1280x720 ${options[*]} &
sleep 12
import -window root "$out"
kill \$!
INNER
chmod +x "$inner"
xvfb-run -a -s "-screen 0 1280x720x24" "$inner"
rm -f "$inner"
echo "wrote $out"
