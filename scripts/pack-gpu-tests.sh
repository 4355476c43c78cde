#!/usr/bin/env bash
# Packs the renderer's GPU tests and the gnomon binary for a machine with a GPU and no Rust
# toolchain (x86-64 Linux, a Vulkan or GL driver): the release test binaries of
# gnomon-render (stripped), target/release/gnomon, the real meshes and the suite's models,
# and run.sh, which runs every test binary on the backend WGPU_BACKEND names (default vulkan)
# and prints one line per binary, then `gnomon bench` on the demo.
#
#   scripts/pack-gpu-tests.sh OUT.tar.xz
#
# On the GPU machine: tar xJf OUT.tar.xz && bash gnomon-gpu-tests/run.sh
# (THREADS: tests at once per binary, default 4; BENCH=0 leaves the bench out.)
# Fetch the models first (scripts/fetch-meshes.sh, scripts/fetch-suite.sh); the monastery is
# packed when it is there, and its views run with GNOMON_SUITE_FULL=1.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ne 1 ] || [[ "$1" != *.tar.xz ]]; then
    echo "usage: scripts/pack-gpu-tests.sh OUT.tar.xz" >&2
    exit 2
fi
out="$(realpath -m "$1")"
[ -d "$(dirname "$out")" ] || { echo "pack-gpu-tests.sh: no folder $(dirname "$out")" >&2; exit 2; }
for d in assets/meshes assets/suite/models; do
    [ -d "$d" ] || { echo "pack-gpu-tests.sh: $d is missing: run scripts/fetch-meshes.sh and scripts/fetch-suite.sh" >&2; exit 2; }
done
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
pack="$stage/gnomon-gpu-tests"
mkdir -p "$pack/tests" "$pack/assets/suite"
cargo build -q --release -p gnomon-cli
cargo test -q --release -p gnomon-render --no-run --message-format=json |
    python3 -c '
import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["profile"]["test"]:
        print(m["executable"])
' | while read -r exe; do
    name="$(basename "$exe")"
    strip -o "$pack/tests/${name%-*}" "$exe"
done
strip -o "$pack/gnomon" target/release/gnomon
cp -r assets/meshes "$pack/assets/meshes"
cp assets/suite/*.toml "$pack/assets/suite/"
mkdir -p "$pack/assets/suite/models"
find assets/suite/models -maxdepth 1 -type f -exec cp {} "$pack/assets/suite/models/" \;
cat > "$pack/run.sh" <<'EOF'
#!/usr/bin/env bash
# The renderer's tests on this machine's GPU, then `gnomon bench` on the demo (see
# scripts/pack-gpu-tests.sh in gnomon). Logs in $LOGS (default ./gpu-test-logs).
set -u
here="$(cd "$(dirname "$0")" && pwd)"
logs="${LOGS:-$PWD/gpu-test-logs}"
mkdir -p "$logs"
export WGPU_BACKEND="${WGPU_BACKEND:-vulkan}" NODEVICE_SELECT=1
export GNOMON_MESH_DIR="$here/assets/meshes" GNOMON_SUITE_DIR="$here/assets/suite"
failed=0
for t in "$here"/tests/*; do
    n="$(basename "$t")"
    start=$(date +%s)
    (cd "$here" && "$t" --test-threads="${THREADS:-4}" --nocapture) > "$logs/$n.log" 2>&1
    rc=$?
    [ $rc = 0 ] || failed=1
    echo "$WGPU_BACKEND $n rc=$rc $(( $(date +%s) - start )) s $(grep -E '^test result' "$logs/$n.log" | tail -1)"
done
if [ "${BENCH:-1}" != 0 ]; then
    "$here/gnomon" bench --techniques focused,lispsm,sppsm,cascades-stable,cascades-lispsm,cascades-best,volumes,volumes-per-caster,planar \
        --size 1920x1080 --frames 20 | tee "$logs/bench.txt"
fi
exit $failed
EOF
chmod +x "$pack/run.sh"
tar cJf "$out" -C "$stage" gnomon-gpu-tests
echo "pack-gpu-tests.sh: wrote $out ($(du -h "$out" | cut -f1))"
