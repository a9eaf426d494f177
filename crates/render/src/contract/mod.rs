//! The contract between nearfield's frame and the techniques, and between the techniques and an
//! engine that lifts them: the formats of the images ([`formats`]), what a technique reads and
//! writes ([`io`]: `NearFieldInputs`, `NearFieldOutputs`, `SceneInputs`), group 0 of every pass
//! ([`frame`]), the light bindings ([`lights`]) and the technique API ([`technique`]).
//!
//! The layers of this crate, each importing only those before it (docs/src/architecture.md):
//! the base (errors, the pipeline cache, bindings, WGSL preludes, uniforms, the environment, the
//! far field, the scene's buffers, settings) → this contract → `passes` → the technique
//! families (`technique/<family>/`) → the registry (`technique`) → the renderer.

pub mod formats;
pub mod frame;
pub mod io;
pub mod lights;
pub mod technique;
