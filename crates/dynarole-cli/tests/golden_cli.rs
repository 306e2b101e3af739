//! Golden command lines: every folder of `tests/golden_cli/` is one case, a `cmd` file (the
//! arguments of one `dynarole` command, split on white space) and the inputs it names. The
//! command runs inside the folder, so messages show the case's own file names; its exit code,
//! standard output and standard error go into one snapshot. Adding a case is adding a folder.

mod common;

use common::text;
use std::path::Path;
use std::process::Command;

/// `$ dynarole ARGS`, the exit code, then what the command printed.
fn run_case(cmd_path: &Path) -> String {
    let cmd = std::fs::read_to_string(cmd_path).unwrap_or_default();
    let args: Vec<&str> = cmd.split_whitespace().collect();
    let dir = cmd_path.parent().unwrap_or(Path::new("."));
    let out = Command::new(env!("CARGO_BIN_EXE_dynarole"))
        .args(&args)
        .current_dir(dir)
        .env_remove("NO_COLOR")
        .output()
        .expect("the dynarole binary runs");
    let code = out
        .status
        .code()
        .map_or_else(|| "killed".to_string(), |c| c.to_string());
    format!(
        "$ dynarole {}\nexit: {code}\n----- stdout -----\n{}----- stderr -----\n{}",
        args.join(" "),
        text(&out.stdout),
        text(&out.stderr)
    )
}

#[test]
fn golden_command_lines() {
    insta::glob!("golden_cli/*/cmd", |path| {
        insta::assert_snapshot!(run_case(path));
    });
}
