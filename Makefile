# The two commands of the README. Both install what is missing first (scripts/setup.sh).
CARGO ?= $(shell command -v cargo 2>/dev/null || echo $(HOME)/.cargo/bin/cargo)
export XDG_RUNTIME_DIR ?= $(shell d=$${TMPDIR:-/tmp}/nearfield-xdg-$$(id -u); mkdir -p -m 700 $$d; echo $$d)

.PHONY: setup demo test lint fuzz

setup:
	@./scripts/setup.sh

# Renders the built-in default scene (open-top Cornell box under the analytic sky) to cornell.png.
demo: setup
	$(CARGO) run --release -p nearfield-cli -- render builtin:cornell -o cornell.png

# Every test: unit, naga shader validation, GPU tests (lavapipe without a GPU), real assets from
# ../shared/assets, bad-input handling. REQUIRE_GPU=1 makes a missing adapter a failure.
test: setup
	$(CARGO) test --workspace

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -- -D warnings

# The fuzzing harness of every input format (crates/fuzz) for FUZZ_SECONDS per format (default
# 60), from FUZZ_SEED (default 1). CI runs the same for 8 s per format in `make test`.
fuzz:
	FUZZ_SECONDS=$${FUZZ_SECONDS:-60} $(CARGO) test --release -p nearfield-fuzz -- --nocapture
