#!/usr/bin/env bash
# Installs what a fresh Debian/Ubuntu machine lacks to build and run nearfield:
# - a Vulkan driver: Mesa's lavapipe (software rasterizer) when no Vulkan ICD is installed;
# - a virtual X server (xvfb, xauth) for the viewer's window tests when xvfb-run is missing;
# - xwd (x11-apps) and ImageMagick's convert, with which the viewer test grabs the X screen;
# - Chromium, in which the report test loads report.html headless;
# - a C++ compiler (nv-flip, the FLIP metric, builds its C++ core) when none is installed;
# - a Rust toolchain through rustup when cargo is missing.
# Idempotent: does nothing when all are present.
set -euo pipefail

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

has_vulkan_driver() {
    # An installed ICD manifest and the loader library are enough for wgpu to find an adapter.
    compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null || compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null || return 1
    ldconfig -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null
}

if ! has_vulkan_driver; then
    echo "setup: no Vulkan driver found; installing Mesa's lavapipe (mesa-vulkan-drivers, libvulkan1)"
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers libvulkan1 >/dev/null
fi

if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "setup: no xvfb-run found; installing xvfb and xauth (the viewer's tests open a window)"
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq --no-install-recommends xvfb xauth >/dev/null
fi

missing=()
command -v xwd >/dev/null 2>&1 || missing+=(x11-apps)
[ -x /usr/bin/convert ] || missing+=(imagemagick)
command -v chromium >/dev/null 2>&1 || missing+=(chromium)
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]} (screen grabs of the viewer, the report in a browser)"
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if ! command -v c++ >/dev/null 2>&1; then
    echo "setup: no C++ compiler found; installing g++ (for the FLIP metric's C++ core)"
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update -qq
    as_root apt-get install -y -qq --no-install-recommends g++ >/dev/null
fi

if ! command -v cargo >/dev/null 2>&1; then
    if [ -x "$HOME/.cargo/bin/cargo" ]; then
        echo "setup: cargo is in ~/.cargo/bin; add it to PATH"
    else
        echo "setup: installing Rust (rustup, stable)"
        curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal
    fi
fi
