//! `nearfield export`: a scene (a built-in or any file we load) with its camera as glTF 2.0, for
//! other engines (the Bevy peer harness, `peers/bevy_ssao`, renders the exported Cornell box).

use crate::BadInput;
use crate::options::SceneOpts;
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ExportArgs {
    #[command(flatten)]
    pub scene: SceneOpts,
    /// Output file: .glb (binary) or .gltf (JSON, buffer embedded). The camera (with `--size`'s
    /// aspect ratio) is the file's camera 0.
    #[arg(long)]
    pub out: PathBuf,
}

pub fn run(args: ExportArgs) -> Result<()> {
    let ext = args
        .out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("glb" | "gltf")) {
        return Err(BadInput(format!(
            "--out {}: expected a .glb or .gltf file name",
            args.out.display()
        ))
        .into());
    }
    crate::output::check_parent_dir(&args.out)?;
    let (w, h) = crate::options::parse_size(&args.scene.size)?;
    let loaded = args.scene.load()?;
    nearfield_scene::export::write_gltf(
        &loaded.scene,
        &loaded.camera,
        w as f32 / h as f32,
        &args.out,
    )?;
    eprintln!(
        "nearfield: wrote {} ({} triangles, {} materials, {} lights, camera 0)",
        args.out.display(),
        loaded.scene.triangle_count(),
        loaded.scene.materials.len(),
        loaded.scene.lights.len()
    );
    Ok(())
}
