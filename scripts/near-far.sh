#!/usr/bin/env bash
# The book's "Near and far" tables: every technique's image error (`lambertian` against the path
# tracer) with the probe volume at several spacings and R = auto (the spacing), on the enclosed
# built-in scenes and Crytek Sponza; and the footprint of the objects the bake never saw
# (`compare --footprint`) on the dynamic variants. Prints markdown on stdout; each run's report is
# kept in target/near-far/. About an hour on 2 cores (the references are cached: a second run
# takes minutes).
#
#   scripts/near-far.sh [spacings]        default spacings: 0.5 1 2 4
#   NEAR_FAR_ONLY=spacings|footprint      one of the two tables
#   METHODS=none,vbgi                     only these techniques' columns (default: all ten)
set -euo pipefail
cd "$(dirname "$0")/.."
N=target/release/nearfield
ASSETS=${NEARFIELD_ASSETS:-../shared/assets}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(d=${TMPDIR:-/tmp}/nearfield-xdg-$(id -u); mkdir -p -m 700 "$d"; echo "$d")}
SPACINGS=${*:-0.5 1 2 4}
METHODS=${METHODS:-none,ssao,ssdo,s3ho,ssbn,gtao,hbil,vbgi,instant-radiosity,ssdo-vpl}
OUT=target/near-far
mkdir -p "$OUT"

SPONZA="$ASSETS/scenes/crytek_sponza/Sponza.gltf --eye 9,1.5,-0.4 --target -5,3.5,0.2 --fov 60 --env $ASSETS/env/rooitou_park_1k.hdr"

# One row: scene, spacing, the reference's relative noise, each method's error (image mean over
# the truth's).
row() {
    python3 - "$1" "$2" "$3/metrics.json" <<'EOF'
import json, sys
name, spacing, path = sys.argv[1:4]
d = json.load(open(path))
cells = []
for m in d["methods"]:
    x = m["metrics"]
    cell = f"{x['relative_error']:.4f} ({x['mean_ratio']:.2f})"
    if m.get("footprint") is not None:
        cell += f" fp {m['footprint']:.2f}"
    cells.append(cell)
print(f"| {name} | {spacing} | {d['reference_relative_noise']:.4f} | " + " | ".join(cells) + " |")
EOF
}

header() {
    echo "| scene | spacing (m) | ref. noise | ${METHODS//,/ | } |"
    echo "|---|---|---|$(printf -- '---|%.0s' $(seq 1 $(($(tr -cd , <<<"$METHODS" | wc -c) + 1))))"
}

compare() { # name spacing args...
    local name=$1 spacing=$2
    shift 2
    local dir="$OUT/$name-$spacing"
    "$N" compare "$@" --spacing "$spacing" --frames 16 --aov lambertian \
        --methods "$METHODS" --out "$dir" >/dev/null 2>"$dir.log" || { cat "$dir.log" >&2; exit 1; }
    row "$name" "$spacing" "$dir"
}

cargo build --release -q -p nearfield-cli --bin nearfield
if [ "${NEAR_FAR_ONLY:-spacings}" = spacings ]; then
    header
    for s in $SPACINGS; do
        for scene in cornell gap columns two-rooms; do
            compare "$scene" "$s" "builtin:$scene" --size 192x144 --spp 1024 --max-depth 8
        done
        compare closed-box "$s" builtin:closed-box --size 192x144 --spp 4096 --max-depth 8
        if [ -f "$ASSETS/scenes/crytek_sponza/Sponza.gltf" ]; then
            # shellcheck disable=SC2086
            compare sponza "$s" $SPONZA --size 160x90 --spp 4608 --max-depth 32
        fi
    done
fi
if [ "${NEAR_FAR_ONLY:-footprint}" = footprint ]; then
    echo
    header
    for scene in cornell-dynamic two-rooms-dynamic; do
        compare "$scene" 1 "builtin:$scene" --size 192x144 --spp 1024 --max-depth 8 --footprint
    done
    if [ -f "$ASSETS/scenes/crytek_sponza/Sponza.gltf" ]; then
        # shellcheck disable=SC2086
        compare sponza-helmet 1 $SPONZA --size 160x90 --spp 4608 --max-depth 32 --footprint \
            --add "$ASSETS/scenes/damaged_helmet/DamagedHelmet.gltf@4.2,-0.02,0.6,0.6"
    fi
fi
