//! The `dynarole` executable; everything lives in the `dynarole_cli` library.

fn main() -> std::process::ExitCode {
    restore_sigpipe();
    dynarole_cli::main()
}

/// Rust ignores SIGPIPE, so writing to a closed pipe (`dynarole simulate ... | head`) would
/// make `println!` panic; with the default disposition the program ends quietly, as other
/// command-line tools do.
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called first thing in main, before any other thread exists; SIG_DFL is a valid
    // disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn restore_sigpipe() {}
