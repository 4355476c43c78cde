#!/usr/bin/env bash
# Runs every check CI runs: formatting, lints and all tests.
#
# Where no Vulkan driver is installed it first installs Mesa's software driver (lavapipe),
# which the renderer's GPU tests run on (this needs root and apt-get, as on CI); it fetches
# the real meshes the shadow-volume tests use (scripts/fetch-meshes.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
# Mesa's device-select layer warns about XDG_RUNTIME_DIR on headless machines; harmless.
export NODEVICE_SELECT=1

if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
        echo "test.sh: no Vulkan driver found; installing Mesa's software Vulkan driver (lavapipe)"
        apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
            mesa-vulkan-drivers libvulkan1 >/dev/null
    else
        echo "test.sh: warning: no Vulkan driver found and none can be installed here (needs root and apt-get)" >&2
    fi
fi

# The shadow-volume tests on real meshes need the bunny and the knot (not committed).
bash scripts/fetch-meshes.sh

echo "test.sh: cargo fmt --check"
cargo fmt --all --check
echo "test.sh: cargo clippy"
cargo clippy --workspace --all-targets --locked -- -D warnings
echo "test.sh: cargo test"
cargo test --workspace --locked
