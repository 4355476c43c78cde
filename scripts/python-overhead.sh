#!/usr/bin/env bash
# The Python bindings' overhead over the Rust core in one run: the two criterion benches the
# bindings are compared with, then the same calls timed from Python (the gnomon wheel
# installed: pip install ./crates/gnomon-py).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench -q --locked -p gnomon-core --bench setup -- \
    '^(setup/cascades_4_lispsm_directional/1000|scale/bounds_and_hierarchies/10000)$' >/dev/null
python3 scripts/python-overhead.py
