//! `nearfield`: see the library's documentation ([`nearfield_cli`]).

fn main() -> std::process::ExitCode {
    nearfield_cli::main()
}
