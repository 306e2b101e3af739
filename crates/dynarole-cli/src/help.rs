//! The examples the help prints, read from `docs/help-examples.txt` (compiled in): the example
//! files live in the robots' folders, so the help's text is documentation beside them rather
//! than code that names a robot.

/// `docs/help-examples.txt`: `[NAME]` lines, each followed by its example's lines.
const EXAMPLES: &str = include_str!("../../../docs/help-examples.txt");

/// Where to go next, after the examples of `dynarole --help`.
const NEXT: &str =
    "`dynarole help COMMAND` shows a command's options and an example. Documentation: the
repository's README.md, and docs/ (language.md: the language; simulator.md, cluster.md,
verification.md, viewer.md, runtime.md, limits.md; robots.md: the robots and how to add one).
Exit codes: 0 success, 1 bad input or a failed check, 2 bad usage, 3 a simulation that did
not reach its goal or a search that could not finish, 4 internal error.";

/// The lines of section `name` of the examples file (empty when there is none: the test of
/// the help requires one for every command).
fn section(name: &str) -> String {
    let header = format!("[{name}]");
    let mut lines = EXAMPLES
        .lines()
        .skip_while(|l| l.trim() != header)
        .skip(1)
        .take_while(|l| !l.starts_with('['));
    let mut out: Vec<&str> = lines.by_ref().collect();
    while out.last().is_some_and(|l| l.trim().is_empty()) {
        out.pop();
    }
    out.join("\n")
}

/// `Example:` and the command's example, for its help.
pub fn example(command: &str) -> String {
    format!("Example:\n{}", section(command))
}

/// What `dynarole --help` ends with: where to start, then where to go next.
pub fn after_help() -> String {
    format!("Start with:\n{}\n\n{NEXT}", section("start"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_section_is_its_lines_without_the_blank_ones_after_it() {
        assert!(section("start").starts_with("  dynarole check "));
        assert!(!section("check").contains('['));
        assert!(!section("check").ends_with('\n'));
        assert_eq!(section("no such command"), "");
    }
}
