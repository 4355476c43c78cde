#!/usr/bin/env bash
# Instructions per shadow-map setup, counted by valgrind's callgrind on the criterion bench's
# city (crates/gnomon/benches/common/city.rs), through the `setup_loop` example. Timings on a
# shared 2-core machine swing by 10 to 20% between runs of the same code; the count is the
# same on every run, so it tells whether a change made a setup cheaper. (It counts
# instructions, not cycles: divisions and cache misses weigh more than it shows; confirm a
# win with `cargo bench -p gnomon-core --bench setup`.)
#
#   scripts/setup-instructions.sh [BOXES] [SETUP ...]
#
# BOXES defaults to 1000; SETUP to every setup the example knows (its usage lists them, as the
# bench names them). To compare two commits, run it in a checkout of each. Each setup runs
# N and 3N times (N scaled to the boxes) and the difference is divided by 2N, so that building
# the scene and loading the program cancel out. Needs valgrind (apt-get install valgrind).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v valgrind >/dev/null; then
    echo "setup-instructions.sh: valgrind is not installed (apt-get install valgrind)" >&2
    exit 2
fi
boxes="${1:-1000}"
if ! [[ "$boxes" =~ ^[1-9][0-9]*$ ]]; then
    echo "setup-instructions.sh: BOXES must be a whole number of at least 1, not '$boxes'" >&2
    exit 2
fi
shift || true
setups=("$@")
if [ ${#setups[@]} -eq 0 ]; then
    setups=(focused_directional lispsm_directional_given_samples
        cascades_4_lispsm_directional_given_samples cascades_adaptive_directional_given_samples
        sppsm_directional cube_point_given_samples
        cube_point_over_city_given_samples)
fi
# Without the opt-in `parallel` feature: the count is the setup's work, done on the calling
# thread (rayon's idle workers spin before they sleep, and callgrind would count that too).
cargo build -q --release -p gnomon-core --example setup_loop
bin=target/release/examples/setup_loop
# About 2 * 10^8 instructions per run at most.
n=$(( 200000 / boxes ))
n=$(( n < 5 ? 5 : (n > 200 ? 200 : n) ))
count() {
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$bin" "$1" "$boxes" "$2" 2>&1 \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}
for s in "${setups[@]}"; do
    "$bin" "$s" 1 0 || exit 2
done
printf '| setup | boxes | instructions per setup |\n| --- | ---: | ---: |\n'
for s in "${setups[@]}"; do
    a=$(count "$s" "$n")
    b=$(count "$s" $((3 * n)))
    printf '| %s | %s | %s |\n' "$s" "$boxes" $(( (b - a) / (2 * n) ))
done
