//! The `dynarole` executable; everything lives in the `dynarole_cli` library.

fn main() -> std::process::ExitCode {
    dynarole_cli::main()
}
