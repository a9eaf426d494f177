//! `nearfield`: render, compute references, compare, benchmark and view screen-space near-field
//! light transport.
//!
//! Exit status: 0 success, 2 bad arguments or unreadable input (one line on stderr), 1 other
//! failures.
//!
//! The binary is [`main`]; the library exposes the command modules so that their parsers (the
//! viewer's script, option checks) can be exercised without a process per input.

pub mod bench;
pub mod book;
pub mod compare;
pub mod export;
pub mod far;
pub mod fit;
pub mod footprint;
pub mod measure;
pub mod options;
pub mod output;
pub mod pareto;
pub mod reference;
pub mod render;
pub mod view;

use clap::{Parser, Subcommand};
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "nearfield",
    version,
    about = "Screen-space near-field light transport: render, compare, benchmark, view"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render one image (or one AOV) of a scene with a near-field technique.
    Render(render::RenderArgs),
    /// Compute the CPU ground truth of one AOV (cached).
    Reference(reference::ReferenceArgs),
    /// Compare techniques with the reference: metrics.json, report.html, images.
    Compare(compare::CompareArgs),
    /// Time every pass of one or more techniques (median and p90 over many frames).
    Bench(bench::BenchArgs),
    /// Fit a technique's numeric settings against the reference; held-out scenes measured.
    Fit(fit::FitArgs),
    /// Error against time of every technique's presets and counts: pareto.json and pareto.svg.
    Pareto(pareto::ParetoArgs),
    /// Write a scene (a built-in or a file) and its camera as glTF 2.0 (.glb or .gltf).
    Export(export::ExportArgs),
    /// Bake the scene's probe volume, the far field beyond R (cached; --volume reads the file).
    Bake(far::BakeArgs),
    /// Interactive viewer: every technique, setting and AOV live, A/B split, timings.
    View(view::ViewArgs),
}

/// An error caused by what the user typed or loaded: exit status 2.
#[derive(Debug)]
pub struct BadInput(pub String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// Exit status for an error: 2 when the user's input is at fault.
pub fn exit_status(e: &anyhow::Error) -> u8 {
    use nearfield_render::RenderError as R;
    for cause in e.chain() {
        if cause.downcast_ref::<BadInput>().is_some()
            || cause
                .downcast_ref::<nearfield_scene::SceneError>()
                .is_some()
        {
            return 2;
        }
        if let Some(r) = cause.downcast_ref::<R>() {
            return match r {
                R::Gpu(_) | R::Device { .. } | R::Lost(_) => 1,
                _ => 2,
            };
        }
    }
    1
}

pub fn init_logging() {
    env_logger::Builder::from_env(env_logger::Env::default().filter_or("NEARFIELD_LOG", "warn"))
        .format(|buf, record| {
            let level = record.level().to_string().to_lowercase();
            writeln!(buf, "nearfield: {level}: {}", record.args())
        })
        // wgpu and naga are loud at warn level about things that are not the user's concern.
        .filter_module("wgpu_core", log::LevelFilter::Error)
        .filter_module("wgpu_hal", log::LevelFilter::Error)
        .filter_module("naga", log::LevelFilter::Error)
        .init();
}

/// Vulkan loaders complain on every start when XDG_RUNTIME_DIR is unset (containers, CI); give
/// them a private one.
pub fn quiet_runtime_dir() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir()) {
        return;
    }
    let dir = std::env::temp_dir().join(format!("nearfield-runtime-{}", std::process::id()));
    #[cfg(unix)]
    {
        use std::os::unix::fs::DirBuilderExt;
        let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    }
    // SAFETY: called first thing in main, before any other thread exists.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
}

/// The `nearfield` command line: parses the arguments, runs the command, prints an error as one
/// line and returns the exit status.
pub fn main() -> ExitCode {
    quiet_runtime_dir();
    init_logging();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if !e.use_stderr() => {
            // --help, --version
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            // clap's first paragraph names the problem (a missing argument on the lines after
            // its first); its usage block would make it several lines.
            let text = e.to_string();
            let paragraph: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            let first = match paragraph.join(" ") {
                p if p.is_empty() => "invalid arguments".to_string(),
                p => p,
            };
            let first = first.strip_prefix("error: ").unwrap_or(&first);
            eprintln!("nearfield: error: {first} (see nearfield --help)");
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Render(a) => render::run(a),
        Command::Reference(a) => reference::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Fit(a) => fit::run(a),
        Command::Pareto(a) => pareto::run(a),
        Command::Export(a) => export::run(a),
        Command::Bake(a) => far::run(a),
        Command::View(a) => view::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let msg = format!("{e:#}").replace('\n', " ");
            eprintln!("nearfield: error: {msg}");
            ExitCode::from(exit_status(&e))
        }
    }
}
