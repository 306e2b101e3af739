//! The front end never panics on generated input: arbitrary bytes and token soup (the fuzz
//! targets' words) go through parse, check, format and the plugin loader; whatever parses
//! cleanly must format to text that parses cleanly. (The corpus-driven targets are in
//! `fuzz_targets.rs`.)

use dynarole_core::format::format_file;
use dynarole_core::{analyze, parse, RobotApi};
use dynarole_fuzz::Target;
use proptest::prelude::*;

fn run_front_end(text: &str) {
    let parsed = parse(text);
    let registry = dynarole_robots::plugins();
    let (program, _) = analyze(&parsed.file, &registry);
    if let Some(program) = program {
        for decl in parsed.file.sequences() {
            let name = &decl.name.name;
            if let Some(plan) = program.expand(name) {
                let _ = plan.flatten_for_paper();
            }
            let _ = program.reverse_sequence(name, "reversed");
        }
    }
    if parsed.diagnostics.is_empty() {
        let formatted = format_file(&parsed.file, text);
        let reparsed = parse(&formatted);
        assert!(
            reparsed.diagnostics.is_empty(),
            "formatting made a valid file invalid:\n{text}\n---\n{formatted}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        run_front_end(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn token_soup_never_panics(words in prop::collection::vec(prop::sample::select(Target::Parse.vocabulary()), 0..80)) {
        run_front_end(&words.join(" "));
    }

    #[test]
    fn plugin_loader_never_panics(text in "[a-z_=\\[\\]\"{}0-9,.\n ]{0,200}") {
        let _ = RobotApi::from_toml(&text);
    }
}

#[test]
fn deep_nesting_is_refused_not_overflowed() {
    let text = format!(
        "robot atron; sequence s {}{}",
        "{".repeat(100_000),
        "}".repeat(100_000)
    );
    run_front_end(&text);
    let role = format!(
        "robot atron; role r requires {}id{};",
        "(".repeat(100_000),
        ")".repeat(100_000)
    );
    run_front_end(&role);
    let chain = format!(
        "robot atron; role r requires id == 0{};",
        " || id == 1".repeat(100_000)
    );
    run_front_end(&chain);
    let negations = format!("robot atron; role r requires {}true;", "!".repeat(100_000));
    run_front_end(&negations);
}
