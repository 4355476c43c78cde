#!/usr/bin/env bash
# Makes the book's technique pictures (docs/src/images/tech-*.png): each technique page names
# the `gnomon render` command of its picture, and this runs it.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -n "${NO_BUILD:-}" ] || cargo build -q --release -p gnomon-cli
for page in docs/src/techniques/*.md; do
    command=$(grep -o '`gnomon render [^`]*`' "$page" | head -1 | tr -d '`') || continue
    [ -n "$command" ] || continue
    name=$(basename "$page" .md)
    # The page names the output as NAME.png; the picture goes to the book's images.
    args=${command#gnomon render }
    args=${args/--out $name.png/--out docs/src/images/tech-$name.png}
    # shellcheck disable=SC2086
    target/release/gnomon render $args 2>/dev/null
    echo "docs/src/images/tech-$name.png"
done
