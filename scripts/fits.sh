#!/usr/bin/env bash
# The fitted presets (`quality=fitted`): every technique's free constants fitted against the
# reference (scenes below). Writes docs/src/fits/TECHNIQUE.json (what
# crates/render/src/settings/fitted.rs quotes, and what the book's results page shows).
#
#   scripts/fits.sh              every technique (about 15 minutes on 2 cores)
#   FITS_ONLY=ssdo scripts/fits.sh
#
# Assets come from ../shared/assets (NEARFIELD_ASSETS); without Sponza the fits use the
# built-in scenes only and say so.
set -euo pipefail
cd "$(dirname "$0")/.."
assets=${NEARFIELD_ASSETS:-../shared/assets}
nf=${NEARFIELD:-target/release/nearfield}
[ -x "$nf" ] || cargo build --release -p nearfield-cli
out=docs/src/fits
# Training: the built-in Cornell box and boxes and one asset scene: Crytek Sponza for occlusion
# and environment light; for one-bounce indirect light the measured Cornell box (McGuire's), since
# Sponza's true bounce within R is nearly zero and every estimate overshoots it (results page).
train=builtin:cornell,builtin:boxes
train_indirect=$train
sponza=$assets/scenes/crytek_sponza/Sponza.gltf
park=$assets/env/rooitou_park_1k.hdr
mcguire=$assets/scenes/cornell_box_mcguire/CornellBox-Original.obj
if [ -f "$sponza" ] && [ -f "$park" ]; then
  train="$train,$sponza@$out/sponza-camera.json:env=$park"
else
  echo "fits: $sponza or $park not found; training on the built-in scenes only" >&2
fi
[ -f "$mcguire" ] && train_indirect="$train_indirect,$mcguire"
# Held out: the other built-in scenes, the Stanford dragon and the Suzanne Cornell box.
holdout=builtin:columns,builtin:city,builtin:closed-box,builtin:gap,builtin:contact,builtin:wall
for f in scenes/stanford_dragon/dragon.obj scenes/cornell_box_suzanne_gltf/cornell-box.glb; do
  [ -f "$assets/$f" ] && holdout="$holdout,$assets/$f"
done
common=(--size 96x54 --radius 1 --spp 256 --holdout "$holdout")

# technique | fitted settings | AOV | frames | fixed settings
fits=(
  "ssao|scale,contrast|env-irradiance|1|"
  "ssdo|strength,distance_clamp|indirect-irradiance|1|"
  "ssdo-vpl|strength,vpl_clamp=0.01..0.5|indirect-irradiance|1|"
  "instant-radiosity|strength,vpl_clamp=0.01..0.5|indirect-irradiance|1|"
  "s3ho|strength,distance_clamp|indirect-irradiance|1|"
  "ssbn|lambda,fade|env-irradiance|1|"
  "gtao|falloff,step_power|ao|16|"
  "hbil|falloff,step_power|diffuse|16|"
  "vbgi|step_power,reject_b|diffuse|16|"
)
for f in "${fits[@]}"; do
  IFS='|' read -r tech params aov frames fixed <<<"$f"
  if [ -n "${FITS_ONLY:-}" ] && [[ ",$FITS_ONLY," != *",$tech,"* ]]; then continue; fi
  set_args=()
  [ -n "$fixed" ] && set_args=(--set "$fixed")
  echo "fits: $tech ($params on $aov, $frames frame(s))" >&2
  scenes=$train
  [ "$aov" = indirect-irradiance ] && scenes=$train_indirect
  "$nf" fit "$tech" --params "$params" --aov "$aov" --frames "$frames" --budget 24 \
    --scenes "$scenes" "${common[@]}" "${set_args[@]}" --out "$out/$tech.json"
done
