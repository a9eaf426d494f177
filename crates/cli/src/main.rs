//! `nearfield`: render, benchmark (and, with later components, compare and view) screen-space
//! near-field light transport.
//!
//! Exit status: 0 success, 2 bad arguments or unreadable input (one line on stderr), 1 other
//! failures.

mod bench;
mod options;
mod render;

use clap::{Parser, Subcommand};
use std::io::Write;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "nearfield",
    version,
    about = "Screen-space near-field light transport: render, compare, benchmark"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render one image (or one AOV) of a scene with a near-field technique.
    Render(render::RenderArgs),
    /// Time every pass of one or more techniques (median and p90 over many frames).
    Bench(bench::BenchArgs),
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
fn exit_status(e: &anyhow::Error) -> u8 {
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
                R::Gpu(_) | R::Device { .. } => 1,
                _ => 2,
            };
        }
    }
    1
}

fn init_logging() {
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

fn main() -> ExitCode {
    init_logging();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        Command::Render(a) => render::run(a),
        Command::Bench(a) => bench::run(a),
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
