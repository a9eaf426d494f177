#!/usr/bin/env python3
"""Writes crates/render/src/settings/fitted.rs from docs/src/fits/*.json (scripts/fits.sh): each
technique's `quality=fitted` preset, every value commented with the fit that produced it and its
training and held-out errors. A test (crates/cli/tests/book.rs) checks that they agree."""
import json, pathlib
root = pathlib.Path(__file__).resolve().parent.parent
out = ['''//! The `quality=fitted` preset of every technique: its free constants fitted against the
//! reference by `nearfield fit` (scripts/fits.sh; the runs are docs/src/fits/TECHNIQUE.json and
//! the book's results page). Written by scripts/fitted-presets.py from those runs: each preset
//! quotes its command, and its error before (the defaults) and after on the training scenes and
//! on held-out scenes it never saw. A held-out error that rose says the constant does not carry
//! over; such presets stay presets, not defaults.

use super::Preset;

/// `quality=fitted` appended to a family's presets.
pub const fn with_fitted<const N: usize>(base: &[Preset], fitted: Preset) -> [Preset; N] {
    let mut out = [fitted; N];
    let mut i = 0;
    while i < base.len() {
        out[i] = base[i];
        i += 1;
    }
    assert!(base.len() + 1 == N, "one fitted preset after the family's");
    out
}''']
# Every fit run (docs/src/fits/TECHNIQUE.json; other files there, such as cameras, have no
# "params"), by technique name.
fits = [(p.stem, json.loads(p.read_text())) for p in sorted((root / "docs/src/fits").glob("*.json"))]
for t, f in fits:
    if "params" not in f or "command" not in f:
        continue
    name = t.upper().replace("-", "_")
    tr, ho = f["train"], f["holdout"]
    change = 100 * (ho["after"] / ho["before"] - 1)
    sets = ", ".join(f'("{k}", "{v}")' for k, v in f["params"].items())
    out.append(f'''
/// `{t}` fitted on `{f["aov"]}` ({f["metric"]}, {f["frames"]} frame{"s" if f["frames"] != 1 else ""}, {f["size"][0]}×{f["size"][1]}, R = {f["radius"]:g} m):
/// training {tr["before"]:.4f} → {tr["after"]:.4f}, held out {ho["before"]:.4f} → {ho["after"]:.4f} ({change:+.1f} %),
/// {f["evaluations"]} evaluations ({f["stopped"]}).
///
/// ```text
/// nearfield {f["command"]}
/// ```
pub const {name}: Preset = Preset {{
    name: "fitted",
    set: &[{sets}],
}};''')
(root / "crates/render/src/settings/fitted.rs").write_text("\n".join(out) + "\n")
print("wrote crates/render/src/settings/fitted.rs")
