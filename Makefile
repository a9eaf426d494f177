# The two commands of the README. Both install what is missing first (scripts/setup.sh).
CARGO ?= $(shell command -v cargo 2>/dev/null || echo $(HOME)/.cargo/bin/cargo)
export XDG_RUNTIME_DIR ?= $(shell d=$${TMPDIR:-/tmp}/nearfield-xdg-$$(id -u); mkdir -p -m 700 $$d; echo $$d)

.PHONY: setup demo test lint fuzz docs figures

setup:
	@./scripts/setup.sh

# Renders the built-in default scene (open-top Cornell box under the analytic sky, its probe volume
# a probe per metre, R = 1 m) with the most accurate technique at interactive cost (hbil, 16
# temporal frames) to cornell.png, and the strip none | ssao | ssdo | s3ho | hbil | vbgi |
# reference of the box with a yellow box the volume's bake never saw (cornell-dynamic), each
# labelled with its relative error against the path-traced reference, to cornell-compare.png
# (report in cornell-compare/).
NEARFIELD = target/release/nearfield
demo: setup
	$(CARGO) build --release -p nearfield-cli
	$(NEARFIELD) render builtin:cornell --method hbil --frames 16 -o cornell.png
	$(NEARFIELD) compare builtin:cornell-dynamic --size 384x288 --aov lambertian --frames 16 \
		--spp 256 --max-depth 8 --methods none,ssao,ssdo,s3ho,hbil,vbgi --out cornell-compare \
		--strip cornell-compare.png
	@echo
	@echo "  $(CURDIR)/cornell.png           hbil, 16 frames, 1280x720"
	@echo "  $(CURDIR)/cornell-compare.png   each technique beside the reference, with its error"
	@echo "  $(CURDIR)/cornell-compare/report.html"
	@echo "  the same scene in the viewer:  $(NEARFIELD) view builtin:cornell --method hbil"

# The book (docs/, mdBook) into target/book/; installs mdbook with cargo when it is missing.
docs:
	@command -v mdbook >/dev/null 2>&1 || [ -x $(HOME)/.cargo/bin/mdbook ] || $(CARGO) install mdbook --locked --version 0.5.4
	PATH="$(HOME)/.cargo/bin:$$PATH" mdbook build docs
	@echo "  $(CURDIR)/target/book/index.html"

# Regenerates every table and figure of the book (minutes; runs renders and references).
figures:
	./scripts/figures.sh

# Every test: unit, naga shader validation, GPU tests (lavapipe without a GPU), real assets from
# ../shared/assets, bad-input handling. REQUIRE_GPU=1 makes a missing adapter a failure. Then the
# test build with a scratch setting and a scratch family (feature `scratch`), their consumers in
# the renderer and the CLI (built for the whole workspace, so that the dependencies keep the
# features of the first build and only nearfield's own crates compile again). Then the
# Bevy plugin (its own workspace; Bevy 0.20.1 declares rust 1.97.1, so the nightly toolchain
# builds it; its `ci` profile, release at opt-level 1, about 11 minutes cold on 2 cores against
# 14 for release) and its one test binary, one test at a time: each test makes nearfield's own
# GPU context beside Bevy's device, and wgpu tells two instances' devices apart by an id that
# both may share (crates/render/src/pipeline_cache.rs).
test: setup
	$(CARGO) test --workspace
	$(CARGO) test --workspace --features nearfield-render/scratch --test scratch
	$(CARGO) test --workspace --features nearfield-render/scratch --lib settings_reach
	cd bevy_nearfield && $(CARGO) +nightly test --profile ci --ignore-rust-version -- --test-threads=1
	BIN=$${CARGO_TARGET_DIR:-target}/debug/nearfield \
		BEVY=$${CARGO_TARGET_DIR:-bevy_nearfield/target}/ci/examples/sponza \
		bash scripts/device-bench.sh --lavapipe

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings
	cd bevy_nearfield && $(CARGO) +nightly fmt -- --check
	cd bevy_nearfield && $(CARGO) +nightly clippy --release --ignore-rust-version --all-targets -- -D warnings

# The fuzzing harness of every input format (crates/fuzz) for FUZZ_SECONDS per format (default
# 60), from FUZZ_SEED (default 1). CI runs the same for 8 s per format in `make test`.
fuzz:
	FUZZ_SECONDS=$${FUZZ_SECONDS:-60} $(CARGO) test --release -p nearfield-fuzz -- --nocapture
