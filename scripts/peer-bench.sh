#!/usr/bin/env bash
# Bevy 0.20's SSAO against nearfield's gtao on the same scene, camera and size, in one command:
# both sides in turn (A B A B), each timing its own frames with the effect off and on; then every
# AO against nearfield's reference; then one table and the ratios.
#
#   scripts/peer-bench.sh                 # 1280x720, builtin:cornell, R = 0.5 m, 2 rounds
#   SIZE=640x360 ROUNDS=3 scripts/peer-bench.sh
#
# Each figure is the median over the rounds (with 2 rounds, their mean).
#
# Each round also times nearfield's `none` frame lit as Bevy's "off" frame is (no light, no shadow
# map: `--sun off --far sky`), and Bevy's frame lit as nearfield's `none` is: "off" plus the same
# sun (elevation, azimuth and radius as nearfield prints them) as a directional light with Bevy's
# cascaded shadow maps (its default filter; soft shadows need the harness built with
# `--features pcss`, which slows every Bevy frame). The base frame both ways round.
#
# Needs: the Bevy harness's toolchain (peers/bevy_ssao/README.md: `cargo +nightly`, Bevy 0.20.1
# declares rust-version 1.97.1), an X display (Xvfb is started when DISPLAY is unset), Vulkan.
# Writes $OUT/peer-bench.json and prints the table. Times on a CPU adapter (lavapipe) are CPU
# times: compare them as ratios within one run.
set -euo pipefail
cd "$(dirname "$0")/.."

SIZE=${SIZE:-1280x720}
SCENE=${SCENE:-builtin:cornell}
RADIUS=${RADIUS:-0.5}
ROUNDS=${ROUNDS:-2}
FRAMES=${FRAMES:-10}
WARMUP=${WARMUP:-5}
SPP=${SPP:-64}
OUT=${OUT:-out/peer-bench}
NF=${NF:-target/release/nearfield}
PEER=peers/bevy_ssao/target/release/bevy-ssao-peer

# Ours at Bevy's budgets (slices × samples per side: low 1×2, medium 2×2, high 3×3, ultra 9×3):
# one pass of samples, evenly spaced (step_power=1), and, like Bevy without TAA, no temporal
# accumulation; the same budget searched at half resolution (one pixel of each 2×2 block,
# upsampled: a quarter of the searches, 18 samples each); then fewer samples, our blur, and gtao at
# its defaults and presets.
MATCHED="+step_power=1+interleaved=off+denoise=off+temporal=off"
OURS=(
  "gtao:slices=1+steps=2$MATCHED"
  "gtao:slices=2+steps=2$MATCHED"
  "gtao:slices=3+steps=3$MATCHED"
  "gtao:slices=9+steps=3$MATCHED"
  "gtao:slices=3+steps=3+resolution=half$MATCHED"
  "gtao:slices=1+steps=4$MATCHED"
  "gtao:slices=1+steps=4+step_power=1+interleaved=off+temporal=off"
  "gtao:slices=3+steps=3"
  "gtao"
  "gtao:resolution=half"
  "gtao:quality=low"
)
BUDGETS=(low medium high ultra high/half - - high - - -)

mkdir -p "$OUT"
if [ ! -x "$NF" ]; then cargo build --release -p nearfield-cli; fi
if [ ! -x "$PEER" ]; then
  (cd peers/bevy_ssao && cargo +nightly build --release --ignore-rust-version)
fi
if [ -z "${DISPLAY:-}" ]; then
  Xvfb :97 -screen 0 1920x1080x24 >/dev/null 2>&1 &
  XVFB=$!
  trap 'kill $XVFB 2>/dev/null || true' EXIT
  export DISPLAY=:97
  sleep 1
fi
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp/nearfield-xdg}
mkdir -p "$XDG_RUNTIME_DIR"

"$NF" export "$SCENE" --size "$SIZE" --out "$OUT/scene.glb"
# The scene's sun as `nearfield render` reports it (none under a map without one).
SUN=$("$NF" render "$SCENE" --method none --size 16x9 -o "$OUT/sun-probe.png" 2>&1 |
  sed -n 's/.*sun at elevation \([-0-9.]*\)°, azimuth \([-0-9.]*\)°, radius \([0-9.]*\)°.*/\1,\2,\3/p')
SUN_ARGS=()
if [ -n "$SUN" ]; then SUN_ARGS=(--sun "$SUN"); fi
methods=$(IFS=,; echo "none,${OURS[*]}")
for round in $(seq 1 "$ROUNDS"); do
  echo "== round $round: Bevy" >&2
  "$PEER" "$OUT/scene.glb" --size "$SIZE" --radius "$RADIUS" --warmup "$WARMUP" \
    --frames "$FRAMES" --rounds 1 "${SUN_ARGS[@]}" --out "$OUT/bevy-$round" >/dev/null
  echo "== round $round: nearfield" >&2
  "$NF" bench "$SCENE" --size "$SIZE" --radius "$RADIUS" --warmup "$WARMUP" \
    --frames "$FRAMES" --methods "$methods" --json "$OUT/ours-$round.json" >/dev/null
  # The base frame as Bevy's "off" draws it: no sun (no light, no shadow map), the sky's SH only.
  "$NF" bench "$SCENE" --size "$SIZE" --warmup "$WARMUP" --frames "$FRAMES" --methods none \
    --sun off --far sky --json "$OUT/ambient-$round.json" >/dev/null
done
images=()
for p in low medium high ultra; do images+=(--image "bevy-$p=$OUT/bevy-1/ao-$p.exr"); done
"$NF" compare "$SCENE" --size "$SIZE" --radius "$RADIUS" --aov ao --spp "$SPP" \
  --methods "$(IFS=,; echo "${OURS[*]}")" "${images[@]}" --out "$OUT/compare" >/dev/null

python3 - "$OUT" "$ROUNDS" "${BUDGETS[*]}" "${OURS[@]}" <<'EOF'
import json, sys, statistics
out, rounds, budgets, ours = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4:]
metrics = {m["name"]: m["metrics"]["relative_error"]
           for m in json.load(open(f"{out}/compare/metrics.json"))["methods"]}
# The median over rounds: one round that a busy machine slowed does not move it.
def mean(v): return statistics.median(v)
bevy = {}
for r in range(1, rounds + 1):
    peer = json.load(open(f"{out}/bevy-{r}/peer.json"))
    for p in peer["presets"]:
        bevy.setdefault(p["preset"], {"samples": p.get("samples"), "overhead": [], "frame": []})
        bevy[p["preset"]]["overhead"].append(p["overhead_ms"])
        bevy[p["preset"]]["frame"].append(p["frame_ms"]["median"])
mine = {}
for r in range(1, rounds + 1):
    b = json.load(open(f"{out}/ours-{r}.json"))
    frame = {m: b["methods"][m]["wall"]["median_ms"] if b["overhead_from"] == "wall"
             else b["methods"][m]["gpu_total"]["median_ms"] for m in b["method_order"]}
    for m in ours:
        mine.setdefault(m, {"overhead": [], "frame": []})
        mine[m]["overhead"].append(frame[m] - frame["none"])
        mine[m]["frame"].append(frame[m])
    mine.setdefault("none", {"frame": []})["frame"].append(frame["none"])
    a = json.load(open(f"{out}/ambient-{r}.json"))
    mine.setdefault("ambient", {"frame": []})["frame"].append(a["methods"]["none"]["wall"]["median_ms"])
rows = []
print(f"{'side':<6} {'configuration':<62} {'spp':>4} {'frame ms':>9} {'overhead ms':>12} {'ao rel err':>10}")
print(f"{'bevy':<6} {'off':<62} {'-':>4} {mean(bevy['off']['frame']):>9.1f} {0:>12.1f} {'-':>10}")
for p in ["low", "medium", "high", "ultra"]:
    b = bevy[p]
    e = metrics[f"bevy-{p}"]
    rows.append({"side": "bevy", "config": p, "samples": b["samples"], "overhead_ms": mean(b["overhead"]),
                 "overheads_ms": b["overhead"], "frame_ms": mean(b["frame"]), "error": e})
    print(f"{'bevy':<6} {p:<62} {b['samples']:>4} {mean(b['frame']):>9.1f} {mean(b['overhead']):>12.1f} {e:>10.4f}")
if "sun" in bevy:
    print(f"{'bevy':<6} {'off + the sun (directional light, cascaded shadow maps)':<62} {'-':>4} {mean(bevy['sun']['frame']):>9.1f} {mean(bevy['sun']['overhead']):>12.1f} {'-':>10}")
print(f"{'ours':<6} {'none':<62} {'-':>4} {mean(mine['none']['frame']):>9.1f} {0:>12.1f} {'-':>10}")
print(f"{'ours':<6} {'none --sun off --far sky (lit as Bevy off: no light, no shadow)':<62} {'-':>4} {mean(mine['ambient']['frame']):>9.1f} {'-':>12} {'-':>10}")
for m, budget in zip(ours, budgets):
    spec = dict(kv.split("=") for kv in m.split(":", 1)[1].split("+")) if ":" in m else {}
    slices, steps = int(spec.get("slices", 2)), int(spec.get("steps", 16))
    if spec.get("quality") == "low": slices, steps = 1, 8
    e = metrics[m]
    rows.append({"side": "ours", "config": m, "budget": budget, "samples": 2 * slices * steps,
                 "overhead_ms": mean(mine[m]["overhead"]), "overheads_ms": mine[m]["overhead"],
                 "frame_ms": mean(mine[m]["frame"]), "error": e})
    print(f"{'ours':<6} {m:<62} {2*slices*steps:>4} {mean(mine[m]['frame']):>9.1f} {mean(mine[m]['overhead']):>12.1f} {e:>10.4f}")
high = next(r for r in rows if r["side"] == "bevy" and r["config"] == "high")
matched = next(r for r in rows if r["side"] == "ours" and r["budget"] == "high")
matched_half = next(r for r in rows if r["side"] == "ours" and r["budget"] == "high/half")
as_good = [r for r in rows if r["side"] == "ours" and r["error"] <= high["error"]]
cheapest = min(as_good, key=lambda r: r["overhead_ms"]) if as_good else None
summary = {
    "bevy_high": high, "ours_at_bevy_high_budget": matched,
    "budget_ratio": matched["overhead_ms"] / high["overhead_ms"],
    "ours_at_bevy_high_budget_half": matched_half,
    "budget_ratio_half": matched_half["overhead_ms"] / high["overhead_ms"],
    "cheapest_as_accurate": cheapest,
    "cheapest_ratio": cheapest["overhead_ms"] / high["overhead_ms"] if cheapest else None,
    "base_frame_ms": {"bevy_off": mean(bevy["off"]["frame"]), "ours_none": mean(mine["none"]["frame"]),
                      "ours_none_ambient": mean(mine["ambient"]["frame"]),
                      "bevy_sun": mean(bevy["sun"]["frame"]) if "sun" in bevy else None},
    "rows": rows, "note": "Bevy's AO is not cosine-weighted (visibility bitmask with constant thickness); the reference is the cosine-weighted AO within R.",
}
json.dump(summary, open(f"{out}/peer-bench.json", "w"), indent=1)
base = summary["base_frame_ms"]
print(f"\nbase frame: ours none {base['ours_none']:.1f} ms = {base['ours_none'] / base['bevy_off']:.2f}x Bevy off "
      f"{base['bevy_off']:.1f} ms; lit as Bevy off (no sun, sky SH) {base['ours_none_ambient']:.1f} ms = "
      f"{base['ours_none_ambient'] / base['bevy_off']:.2f}x")
if base["bevy_sun"]:
    print(f"base frame with the sun on both sides: ours none {base['ours_none']:.1f} ms = "
          f"{base['ours_none'] / base['bevy_sun']:.2f}x Bevy's off + sun {base['bevy_sun']:.1f} ms")
print(f"ours at Bevy High's budget (18 spp): {matched['overhead_ms']:.1f} ms vs Bevy High {high['overhead_ms']:.1f} ms "
      f"= {summary['budget_ratio']:.2f}x; error {matched['error']:.4f} vs {high['error']:.4f}")
print(f"the same at half resolution: {matched_half['overhead_ms']:.1f} ms = {summary['budget_ratio_half']:.2f}x; "
      f"error {matched_half['error']:.4f}")
if cheapest:
    print(f"cheapest of ours at least as accurate as Bevy High ({high['error']:.4f}): {cheapest['config']} "
          f"{cheapest['overhead_ms']:.1f} ms = {summary['cheapest_ratio']:.2f}x Bevy High's, error {cheapest['error']:.4f}")
else:
    print("none of ours is as accurate as Bevy High")
print(f"wrote {out}/peer-bench.json")
EOF
