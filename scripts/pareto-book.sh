#!/usr/bin/env bash
# The book's error-versus-time fronts: `nearfield pareto` for every technique on the built-in
# Cornell box and on Crytek Sponza (../shared/assets), for ao, env-irradiance,
# indirect-irradiance and lambertian. Writes docs/src/pareto/SCENE-AOV/pareto.{json,svg}, which
# the results page shows (`cargo run -p nearfield-cli --example book_reference` writes the table).
#
#   scripts/pareto-book.sh                   # everything (about 40 minutes on 2 cores)
#   PARETO_SCENES=cornell PARETO_AOVS=ao scripts/pareto-book.sh
set -euo pipefail
cd "$(dirname "$0")/.."
assets=${NEARFIELD_ASSETS:-../shared/assets}
nf=${NEARFIELD:-target/release/nearfield}
[ -x "$nf" ] || cargo build --release -p nearfield-cli
out=docs/src/pareto
size=${PARETO_SIZE:-160x90}
common=(--size "$size" --radius 1 --spp 256 --frames 8 --warmup 3 --timed 15)
sponza=$assets/scenes/crytek_sponza/Sponza.gltf
park=$assets/env/rooitou_park_1k.hdr
for scene in ${PARETO_SCENES:-cornell sponza}; do
  case $scene in
    cornell) args=(builtin:cornell) ;;
    sponza)
      if [ ! -f "$sponza" ] || [ ! -f "$park" ]; then
        echo "pareto-book: $sponza or $park not found; Sponza left out" >&2
        continue
      fi
      args=("$sponza" --camera docs/src/fits/sponza-camera.json --env "$park") ;;
    *) echo "pareto-book: unknown scene $scene" >&2; exit 2 ;;
  esac
  for aov in ${PARETO_AOVS:-ao env-irradiance indirect-irradiance lambertian}; do
    case $aov in
      # Techniques that estimate indirect light (the others write none).
      indirect-irradiance) methods=ssdo,ssdo-vpl,instant-radiosity,s3ho,hbil,vbgi ;;
      *) methods=ssao,ssdo,ssdo-vpl,instant-radiosity,s3ho,ssbn,gtao,hbil,vbgi ;;
    esac
    # On Sponza every configuration of ssdo-vpl and instant-radiosity renders its 64 shadow
    # maps of 262 k triangles (about 40 s each on lavapipe): they are measured on the Cornell
    # box only.
    if [ "$scene" = sponza ]; then
      methods=$(echo "$methods" | sed 's/ssdo-vpl,//; s/instant-radiosity,//')
    fi
    mkdir -p "$out/$scene-$aov"
    echo "== $scene $aov" >&2
    "$nf" pareto "${args[@]}" --aov "$aov" --methods "$methods" "${common[@]}" \
      --out "$out/$scene-$aov" > "$out/$scene-$aov/table.txt"
  done
done
