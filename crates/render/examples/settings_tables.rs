//! Prints the README's settings tables, generated from the settings declarations
//! (`nearfield_render::settings`), or rewrites them in place:
//!
//! ```text
//! cargo run -p nearfield-render --example settings_tables             # print
//! cargo run -p nearfield-render --example settings_tables -- --write README.md
//! ```

use nearfield_render::settings::{FAMILIES, markdown_table, rewrite_readme};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => {
            for (id, techniques, table, presets) in FAMILIES {
                println!("<!-- settings:{id} --> ({techniques})");
                println!("{}", markdown_table(table, presets));
            }
        }
        [flag, path] if flag == "--write" => {
            let text = std::fs::read_to_string(path).unwrap_or_else(|e| {
                eprintln!("{path}: {e}");
                std::process::exit(2)
            });
            match rewrite_readme(&text) {
                Ok(new) => nearfield_scene::atomic::write_bytes(path.as_ref(), new.as_bytes())
                    .expect("write README"),
                Err(e) => {
                    eprintln!("{e}");
                    std::process::exit(2)
                }
            }
        }
        _ => {
            eprintln!("usage: settings_tables [--write README.md]");
            std::process::exit(2)
        }
    }
}
