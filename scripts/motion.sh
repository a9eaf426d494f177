#!/usr/bin/env bash
# The book's "In motion" figures: every technique along the moving variants' animations
# (`compare --every 1`: each frame's error, its mean over the still camera's, the instability),
# and the Sponza walk with a ball rolling through the arcade (frames 40, 80 and 120: technique |
# reference | error) as docs/src/motion/sponza-walk.png. Prints each run's per-frame summary;
# the reports are kept in target/motion/. About 30 minutes on 2 cores (references are cached).
#
#   MOTION_ONLY=moving|sponza    one of the two
#   METHODS=none,s3ho             only these techniques on the moving variants (default: all ten)
set -euo pipefail
cd "$(dirname "$0")/.."
N=target/release/nearfield
ASSETS=${NEARFIELD_ASSETS:-../shared/assets}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(d=${TMPDIR:-/tmp}/nearfield-xdg-$(id -u); mkdir -p -m 700 "$d"; echo "$d")}
METHODS=${METHODS:-none,ssao,ssdo,s3ho,gtao,ssbn,hbil,vbgi,ssdo-vpl,instant-radiosity}
OUT=target/motion
mkdir -p "$OUT" docs/src/motion
cargo build --release -p nearfield-cli

if [ "${MOTION_ONLY:-moving}" = moving ]; then
    for s in cornell-moving columns-moving; do
        echo "== $s"
        $N compare builtin:$s --every 1 --size 96x72 --spp 256 --max-depth 8 --aov lambertian \
            --methods $METHODS --out "$OUT/$s" 2>&1 | grep -E "along the path|relative noise"
    done
fi

if [ "${MOTION_ONLY:-sponza}" = sponza ]; then
    # The far-field page's Sponza view, walked; a 0.375 m ball rolls 4.8 m down the nave towards
    # the camera in the first 2 s and stands still after, 5 m ahead of the last frame's camera.
    echo "== sponza walk with a rolling ball"
    $N compare "$ASSETS/scenes/crytek_sponza/Sponza.gltf" --eye 9,1.5,-0.4 --target -5,3.5,0.2 \
        --fov 60 --env "$ASSETS/env/rooitou_park_1k.hdr" --add builtin:rolling-ball@-6,-0.02,0.4,1.5 \
        --walk --every 40 --size 192x108 --spp 512 --max-depth 16 --aov lambertian --exposure 5 \
        --methods none,hbil,vbgi --out "$OUT/sponza" 2>&1 | grep -E "along the path|relative noise"
    f="$OUT/sponza/frames"
    tiles=()
    for i in 0040 0080 0120; do
        n=$((10#$i))
        tiles+=(-label "hbil, frame $n" "$f/hbil-$i.png" -label "vbgi, frame $n" "$f/vbgi-$i.png"
            -label "reference, frame $n" "$f/reference-$i.png" -label "vbgi's error" "$f/vbgi-$i-error.png")
    done
    montage "${tiles[@]}" -tile 4x3 -geometry +2+2 -font DejaVu-Sans -pointsize 11 docs/src/motion/sponza-walk.png
    echo "wrote docs/src/motion/sponza-walk.png (rows: frames 40, 80, 120; hbil | vbgi | reference | vbgi's error)"
fi
