//! The book's generated pages (docs/src/generated/): the command-line reference, read from the
//! clap definitions, and the settings tables, read from the settings declarations, so that
//! neither can drift from the program. `cargo run -p nearfield-cli --example book_reference`
//! writes them; `tests/book.rs` checks that the committed ones are current.

use clap::CommandFactory;
use std::fmt::Write as _;

/// Text for a markdown table cell: one line, `|` escaped.
fn cell(s: &str) -> String {
    s.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace('|', "\\|")
}

/// How an argument is written on the command line.
fn spelling(arg: &clap::Arg) -> String {
    let value = arg
        .get_value_names()
        .map(|v| {
            v.iter()
                .map(|n| format!("<{n}>"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_else(|| format!("<{}>", arg.get_id().as_str().to_uppercase()));
    let takes_value = arg.get_num_args().is_some_and(|n| n.takes_values())
        || (arg.get_num_args().is_none() && arg.get_action().takes_values());
    if arg.is_positional() {
        return format!("[{}]", value.trim_matches(|c| c == '<' || c == '>'));
    }
    let mut names = Vec::new();
    if let Some(s) = arg.get_short() {
        names.push(format!("-{s}"));
    }
    if let Some(l) = arg.get_long() {
        names.push(format!("--{l}"));
    }
    let names = names.join(", ");
    if takes_value {
        format!("{names} {value}")
    } else {
        names
    }
}

/// The command-line reference: every subcommand with its usage and a table of its arguments
/// (spelling, meaning, default).
pub fn cli_reference() -> String {
    let mut cli = crate::Cli::command();
    cli.build();
    let mut out = String::from(
        "<!-- generated from the clap definitions (crates/cli/src/); regenerate with \
         `cargo run -p nearfield-cli --example book_reference` -->\n\n## Reference of every \
         option\n\n",
    );
    for sub in cli.get_subcommands_mut() {
        let name = sub.get_name().to_string();
        let about = sub.get_about().map(|a| a.to_string()).unwrap_or_default();
        let usage = sub.render_usage().to_string();
        let usage = usage.trim_start_matches("Usage: ");
        let _ = write!(
            out,
            "### `nearfield {name}`\n\n{about}\n\n```text\n{}\n```\n\n| argument | meaning | default |\n|---|---|---|\n",
            usage
        );
        for arg in sub.get_arguments() {
            if arg.is_hide_set() || matches!(arg.get_id().as_str(), "help" | "version") {
                continue;
            }
            let help = arg
                .get_long_help()
                .or(arg.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default();
            let values: Vec<String> = arg
                .get_possible_values()
                .iter()
                .filter(|v| !v.is_hide_set())
                .map(|v| format!("`{}`", v.get_name()))
                .collect();
            let help = if values.is_empty() || help.contains(values[0].trim_matches('`')) {
                help
            } else {
                format!("{help} ({})", values.join(", "))
            };
            let default: Vec<String> = arg
                .get_default_values()
                .iter()
                .map(|v| v.to_string_lossy().into_owned())
                .collect();
            let default = if default.is_empty() {
                String::new()
            } else {
                format!("`{}`", default.join(","))
            };
            let _ = writeln!(
                out,
                "| `{}` | {} | {} |",
                cell(&spelling(arg)),
                cell(&help),
                default
            );
        }
        out.push('\n');
    }
    out
}

/// Every generated page: (file name in docs/src/generated/, content); the results pages when
/// measured results are given.
pub fn generated_pages(
    results: Option<&Results>,
    fits: &[Fit],
    fronts: &[Front],
) -> Vec<(String, String)> {
    let mut pages = nearfield_render::technique::book_pages();
    pages.push(("cli.md".into(), cli_reference()));
    if !fits.is_empty() {
        pages.push(("fits.md".into(), fits_page(fits)));
    }
    if !fronts.is_empty() {
        pages.push(("pareto.md".into(), fronts_page(fronts)));
    }
    if let Some(r) = results {
        pages.extend(results_pages(r));
    }
    pages
}

/// Reads docs/src/generated/results.json below `root` (the repository), if it is there.
pub fn read_results(root: &std::path::Path) -> Result<Option<Results>, String> {
    let path = root.join("docs/src/generated/results.json");
    match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

mod fits;
mod fronts;
mod results;
pub use fits::*;
pub use fronts::*;
pub use results::*;
