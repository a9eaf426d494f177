//! Prints what `--sun auto` finds in each map named on the command line:
//! `cargo run -p nearfield-scene --example find_sun -- MAP.hdr...`

fn main() {
    for arg in std::env::args().skip(1) {
        let source = match nearfield_scene::EnvSource::parse(&arg) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        match source.load_split(nearfield_scene::SunMode::Auto) {
            Ok((_, Some(line))) => println!("{line}"),
            Ok((_, None)) => println!("{arg}: no sun"),
            Err(e) => eprintln!("{e}"),
        }
    }
}
