#!/usr/bin/env bash
# The book's and the README's pictures of the Bevy plugin (docs/src/bevy.md): Crytek Sponza in
# the plugin's example with its baked volume (`nearfield bake --format bevy`, the scene's own
# light in Bevy's units), without nearfield and with vbgi High, 1280×720 after 60 frames, saved
# by the example's --screenshot under Xvfb, then scaled (ImageMagick): bevy-sponza-off.png and
# bevy-sponza-vbgi.png at 960×540, and bevy-sponza-pair.png, both at 640×360 side by side.
# Then the far field's strip, bevy-sponza-far.png: the example's linear frames at 640×360
# (`--linear`, exposure 0, 30 frames) with the environment map alone and with vbgi reading it,
# with the volume alone and with the volume and vbgi, beside
# nearfield's `none` (its lambertian part) and the path tracer (`nearfield compare --image …
# --strip`, 256 spp), all at +8 EV; its report (target/figures/bevy-far/compare) has the errors
# and means the book lists.
# PROFILE=ci uses `make test`'s build of the example instead of a release build.
# Needs the nightly toolchain (Bevy declares rust 1.97.1), xvfb-run and convert (scripts/setup.sh
# installs both); about 7 minutes on lavapipe once Bevy is built.
set -euo pipefail
cd "$(dirname "$0")/.."
CARGO=${CARGO:-$(command -v cargo || echo "$HOME/.cargo/bin/cargo")}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(d=${TMPDIR:-/tmp}/nearfield-xdg-$(id -u); mkdir -p -m 700 "$d"; echo "$d")}
img=docs/src/img
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
profile=${PROFILE:-release}
"$CARGO" build --release -p nearfield-cli
target/release/nearfield bake ../shared/assets/scenes/crytek_sponza/Sponza.gltf --format bevy \
    --out "$tmp/sponza.ktx2"
(cd bevy_nearfield && "$CARGO" +nightly build --profile "$profile" --ignore-rust-version --example sponza)
for technique in off vbgi; do
    xvfb-run -a -s '-screen 0 1920x1080x24' "bevy_nearfield/target/$profile/examples/sponza" \
        --technique "$technique" --volume "$tmp/sponza.ktx2" --frames 60 \
        --screenshot "$tmp/$technique.png"
done
convert "$tmp/off.png" -resize 960x540 "$img/bevy-sponza-off.png"
convert "$tmp/vbgi.png" -resize 960x540 "$img/bevy-sponza-vbgi.png"
convert "$tmp/off.png" -resize 640x360 "$tmp/off-small.png"
convert "$tmp/vbgi.png" -resize 640x360 "$tmp/vbgi-small.png"
convert "$tmp/off-small.png" "$tmp/vbgi-small.png" +append "$img/bevy-sponza-pair.png"
echo "  $img/bevy-sponza-off.png, bevy-sponza-vbgi.png, bevy-sponza-pair.png"
far=target/figures/bevy-far
mkdir -p "$far"
images=()
for run in "bevy:off:" "bevy-vbgi:vbgi:" "bevy-volume:off:--volume $tmp/sponza.ktx2" \
    "bevy-volume-vbgi:vbgi:--volume $tmp/sponza.ktx2"; do
    IFS=: read -r name technique volume <<<"$run"
    # shellcheck disable=SC2086 # $volume is two words or none
    xvfb-run -a -s '-screen 0 1920x1080x24' "bevy_nearfield/target/$profile/examples/sponza" \
        --technique "$technique" $volume --exposure 0 --size 640x360 --frames 30 \
        --linear "$far/$name.exr"
    images+=(--image "$name=$far/$name.exr")
done
target/release/nearfield compare ../shared/assets/scenes/crytek_sponza/Sponza.gltf \
    --camera docs/src/fits/sponza-camera.json --size 640x360 --aov lambertian --methods none \
    --spp 256 --max-depth 8 --exposure 8 "${images[@]}" --strip "$img/bevy-sponza-far.png" \
    --out "$far/compare"
echo "  $img/bevy-sponza-far.png"
