#!/usr/bin/env bash
# One prepared benchmark for a lent GPU machine (an NVIDIA H200 through the workplace's device
# tool; ../shared/MACHINE.md). It times every registered technique, gtao/hbil/vbgi with
# interleaved=on and off and at half resolution, and a few presets, at 1280×720 and 1920×1080
# with `nearfield bench` (timestamp queries, per-pass medians after warm-up), and writes into
# $OUT (default out/device-bench):
#   bench-1280x720.json, bench-1920x1080.json   `nearfield bench --json` reports
#   device-bench.md                              one markdown table: per-pass and frame medians
#   pareto-gtao/pareto.{json,svg}                gtao's error-versus-time front at 1920×1080
#   device-bench.log                             everything it printed
# Frames and warm-up were sized to finish within 8 minutes on that machine with one method fewer
# (vbgi:resolution=half, 1 of 20, came later; not yet run on a GPU).
#
# The device machine has no Rust toolchain and no network, so the release binary is built here
# and carried:
#   bash scripts/device-bench.sh --prepare     # here: release build → .device/nearfield,
#                                              # the plugin's example → .device/sponza.xz,
#                                              # Vulkan/EGL loader packages → .gl/
# then on the device (device tool `run`, carry [".device", ".gl"], timeout_s 600):
#   bash scripts/device-bench.sh
# Where cargo exists on the machine it runs on and no carried binary is there, it builds release
# itself.
#
# Each frame's first timed pass is an empty one, `lead` (crates/render/src/profiler.rs): on the
# H200 run the G-buffer of a 28-triangle box read 0.946 ms at 1280×720, nearly the whole `none`
# frame, which a first timestamp written while the GPU still works on the frame before would
# give. The lead takes that wait, and the frame's total leaves it out; the table lists it.
#
#   bash scripts/device-bench.sh --lavapipe    # the same run on a CPU adapter, small and short
#                                              # (CI, `make test`, with BEVY= the example its
#                                              # plugin tests built): every method must report
set -euo pipefail
cd "$(dirname "$0")/.."

LAVAPIPE=0
if [ "${1:-}" = "--lavapipe" ]; then
    LAVAPIPE=1
    SIZES=${SIZES:-160x90}
    FRAMES=${FRAMES:-2}
    WARMUP=${WARMUP:-1}
    OUT=${OUT:-target/device-bench-lavapipe}
fi

# SIZES, PARETO_SIZE, FRAMES, WARMUP, SCENE and BIN (a nearfield binary) may be set to try the
# script elsewhere.
read -ra SIZES <<<"${SIZES:-1280x720 1920x1080}"
PARETO_SIZE=${PARETO_SIZE:-1920x1080}
FRAMES=${FRAMES:-40}
WARMUP=${WARMUP:-8}
SCENE=${SCENE:-builtin:cornell}

if [ "${1:-}" = "--prepare" ]; then
    cargo build --release -p nearfield-cli
    mkdir -p .device
    cp target/release/nearfield .device/nearfield
    strip .device/nearfield 2>/dev/null || true
    # The plugin's example for Bevy's side (its --bench --headless), compressed to fit the carry.
    (cd bevy_nearfield && cargo +nightly build --release --ignore-rust-version --example sponza)
    cp bevy_nearfield/target/release/examples/sponza .device/sponza
    strip .device/sponza 2>/dev/null || true
    xz -T0 -6 -f .device/sponza
    grep -qx '/.device/' .git/info/exclude 2>/dev/null || echo /.device/ >>.git/info/exclude
    grep -qx '/.gl/' .git/info/exclude 2>/dev/null || echo /.gl/ >>.git/info/exclude
    if [ ! -d .gl ] || [ -z "$(ls .gl/*.deb 2>/dev/null)" ]; then
        mkdir -p .gl /tmp/amd64/partial
        o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
        # shellcheck disable=SC2086
        apt-get $o update -qq
        # shellcheck disable=SC2086
        (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    fi
    ls -la .device .gl
    exit 0
fi

OUT=${OUT:-out/device-bench}
mkdir -p "$OUT"
exec > >(tee "$OUT/device-bench.log") 2>&1

# The Vulkan loader, when the machine lacks it (carried as .deb packages, unpacked into /).
if [ "$LAVAPIPE" = 0 ] && ! ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; then
    for f in .gl/*.deb; do [ -e "$f" ] && dpkg -x "$f" /; done
    ldconfig
fi
if [ -e /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
    export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
export WGPU_DEBUG=0

if [ -n "${BIN:-}" ]; then
    :
elif [ "$LAVAPIPE" = 1 ]; then
    # A dev build: the timings are not the point here (`make test` passes the one its tests
    # built as BIN).
    "${CARGO:-cargo}" build -p nearfield-cli
    BIN=${CARGO_TARGET_DIR:-target}/debug/nearfield
elif [ -x .device/nearfield ]; then
    BIN=.device/nearfield
elif command -v cargo >/dev/null 2>&1; then
    cargo build --release -p nearfield-cli
    BIN=target/release/nearfield
else
    echo "device-bench: no .device/nearfield and no cargo; run 'bash scripts/device-bench.sh --prepare' first" >&2
    exit 2
fi
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || true

# Every registered technique, and the horizon techniques at full and half resolution too.
METHODS=none,ssao,ssdo,ssdo-vpl,instant-radiosity,s3ho,ssbn,gtao,gtao:interleaved=off,gtao:resolution=half,gtao:quality=high,gtao:slices=3+steps=3,hbil,hbil:interleaved=off,hbil:resolution=half,hbil:denoise=svgf,vbgi,vbgi:thickness=adaptive,vbgi:interleaved=off,vbgi:resolution=half
start=$(date +%s)
for size in "${SIZES[@]}"; do
    echo "== $size"
    timeout 210 "$BIN" bench "$SCENE" --size "$size" --frames "$FRAMES" --warmup "$WARMUP" \
        --methods "$METHODS" --json "$OUT/bench-$size.json"
done
# gtao's error-versus-time front with GPU timestamps (not on lavapipe: its error needs a
# reference).
[ "$LAVAPIPE" = 1 ] || timeout 150 "$BIN" pareto "$SCENE" --size "$PARETO_SIZE" --methods gtao --aov ao --radius 1 --spp 16 \
    --warmup 10 --timed 30 --out "$OUT/pareto-gtao" || echo "device-bench: pareto did not finish"
echo "device-bench: $(($(date +%s) - start)) s of benchmarks"

# Bevy's side on the same card and in the same run: the plugin's example, headless, on the
# Cornell box as `nearfield export` writes it, at the last size: off, Bevy's SSAO Low, Medium,
# High and Ultra, gtao, hbil, vbgi and gtao at Bevy High's budget inside Bevy, A B A B, each
# effect's GPU time from Bevy's render diagnostics (its `ssao` span, the plugin's `nearfield`
# spans). BEVY names the example's binary; else the carried .device/sponza.xz.
BEVY=${BEVY:-}
if [ -z "$BEVY" ] && [ -f .device/sponza.xz ]; then
    python3 -c 'import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), open(sys.argv[2], "wb"))' \
        .device/sponza.xz "$OUT/sponza"
    chmod +x "$OUT/sponza"
    BEVY=$OUT/sponza
fi
if [ -n "$BEVY" ]; then
    bevy_size=${SIZES[${#SIZES[@]} - 1]}
    "$BIN" export builtin:cornell --size "$bevy_size" --out "$OUT/cornell.glb"
    timeout 300 "$BEVY" "$OUT/cornell.glb" --bench --headless --size "$bevy_size" \
        --bench-frames "${BEVY_FRAMES:-$FRAMES}" | grep '^|' >"$OUT/bevy-bench.md"
    echo "### Bevy at $bevy_size, the exported Cornell box (the plugin's example --bench --headless)"
    echo
    cat "$OUT/bevy-bench.md"
    # Every configuration has its row.
    [ "$(grep -c '^| [a-z]' "$OUT/bevy-bench.md")" -ge 10 ] ||
        { echo "device-bench: Bevy's table is incomplete" >&2; exit 1; }
else
    echo "device-bench: no Bevy example (BEVY=… or .device/sponza.xz): Bevy's side not run"
fi

python3 - "$OUT" "${SIZES[@]}" <<'PY'
import json, sys
out, sizes = sys.argv[1], sys.argv[2:]
lines = []
for size in sizes:
    r = json.load(open(f"{out}/bench-{size}.json"))
    a = r["adapter"]
    lines.append(f"### {size}, {r['settings']['scene']} — {a['name']} ({a['backend']}), "
                 f"{r['settings']['frames']} frames after {r['settings']['warmup']} warm-up\n")
    lines.append("| method | frame (GPU, ms) | lead (ms) | technique passes (ms) | per pass (median ms) |")
    lines.append("|---|---|---|---|---|")
    frame_passes = {"lead", "gbuffer", "shadows", "direct", "composite", "tonemap"}
    for m in r["method_order"]:
        res = r["methods"][m]
        if not res.get("gpu_total") or "lead" not in res["passes"]:
            sys.exit(f"device-bench: {m} at {size} reported no GPU timings")
        total = res["gpu_total"]["median_ms"]
        lead = res["passes"]["lead"]["median_ms"]
        own = sum(res["passes"][p]["median_ms"] for p in res["pass_order"] if p not in frame_passes)
        per = ", ".join(f"{p} {res['passes'][p]['median_ms']:.3f}" for p in res["pass_order"] if p != "lead")
        lines.append(f"| `{m}` | {total:.3f} | {lead:.3f} | {own:.3f} | {per} |")
    lines.append("")
open(f"{out}/device-bench.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
