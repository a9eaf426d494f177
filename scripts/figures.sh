#!/usr/bin/env bash
# Regenerates every table of numbers and every figure of the book (docs/): builds the release
# CLI, measures (crates/cli/examples/figures.rs: compare and bench runs, failure strips, the demo
# strip → docs/src/generated/results.json and docs/src/img/), then renders the generated pages
# and the README's headline table from the measurements (examples/book_reference.rs).
# Tens of minutes on lavapipe; FIGURES_QUICK=1 tries the pipeline at a small size;
# FIGURES_ONLY=bench measures only the frame times again (minutes), dated in results.json;
# FIGURES_ONLY=lambertian only the `lambertian` runs (the image at the far field's defaults).
set -euo pipefail
cd "$(dirname "$0")/.."
CARGO=${CARGO:-$(command -v cargo || echo "$HOME/.cargo/bin/cargo")}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(d=${TMPDIR:-/tmp}/nearfield-xdg-$(id -u); mkdir -p -m 700 "$d"; echo "$d")}
"$CARGO" build --release -p nearfield-cli --bin nearfield --example figures --example book_reference
"$CARGO" run --release -q -p nearfield-cli --example figures
"$CARGO" run --release -q -p nearfield-cli --example book_reference
# The Bevy plugin's pictures (nightly toolchain; builds Bevy once); not with FIGURES_ONLY.
if [ -z "${FIGURES_ONLY:-}" ]; then ./scripts/bevy-figures.sh; fi
