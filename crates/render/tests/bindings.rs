//! Every pass's bindings in Rust agree with its WGSL, by naga's reflection (no GPU needed): each
//! binding the entry point uses is declared by the pass's binding struct under the same name,
//! group and number with the same type, format and access; and each binding the struct declares
//! is declared so in the WGSL.

use nearfield_render::bindings::{FrameBindings, Slot};

/// Every mismatch between a pass's WGSL and its groups (the frame's and its own).
fn check(name: &str, source: &str, entry_point: &str, group1: &[(&str, Slot)]) -> Vec<String> {
    nearfield_render::reflect::group_mismatches(
        name,
        source,
        entry_point,
        &[FrameBindings::SLOTS, group1],
    )
}

#[test]
fn every_pass_binds_what_its_wgsl_declares() {
    let passes = nearfield_render::pass_layouts();
    assert!(passes.len() >= 10, "only {} passes declared", passes.len());
    let errors: Vec<String> = passes
        .iter()
        .flat_map(|p| check(p.name, &p.source, p.entry_point, p.group1))
        .collect();
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn the_check_catches_a_renamed_or_renumbered_binding() {
    // The tonemap pass, then the same WGSL with its two bindings swapped and one renamed.
    let pass = nearfield_render::pass_layouts()
        .into_iter()
        .find(|p| p.name == "tonemap")
        .expect("tonemap pass");
    assert!(check(pass.name, &pass.source, pass.entry_point, pass.group1).is_empty());
    let swapped = pass
        .source
        .replace("@group(1) @binding(0)", "@group(1) @binding(9)")
        .replace("@group(1) @binding(1)", "@group(1) @binding(0)")
        .replace("@group(1) @binding(9)", "@group(1) @binding(1)");
    assert!(!check(pass.name, &swapped, pass.entry_point, pass.group1).is_empty());
    let format = pass.source.replace("rgba8unorm", "rgba16float");
    assert!(!check(pass.name, &format, pass.entry_point, pass.group1).is_empty());
}
