//! End-to-end tests on `examples/campaigns/smoke.toml`: one row per run with the right columns,
//! a resumed campaign gives the rows of an uninterrupted one, plots are written, and errors in
//! the campaign file name their field.

use dynarole_campaign::{run, CampaignFile, Done, Options, Quiet, COLUMNS};
use std::path::{Path, PathBuf};

fn smoke() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/campaigns/smoke.toml")
}

fn options(out: &Path, max_runs: Option<u64>, plots: bool) -> Options {
    Options {
        campaign: smoke(),
        out_dir: out.to_path_buf(),
        max_runs,
        jobs: Some(2),
        plots,
        shard: None,
    }
}

fn campaign(out: &Path, max_runs: Option<u64>, plots: bool) -> Done {
    match run(
        &options(out, max_runs, plots),
        &dynarole_robots::robots(),
        &mut Quiet,
    ) {
        Ok(done) => done,
        Err(e) => panic!("campaign failed: {e}"),
    }
}

/// The data lines of runs.csv, sorted by run index.
fn sorted_rows(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv");
    let mut lines: Vec<String> = text.lines().skip(1).map(str::to_string).collect();
    lines.sort_by_key(|l| l.split(',').next().and_then(|n| n.parse::<u64>().ok()));
    lines
}

#[test]
fn one_row_per_run_with_the_columns() {
    let dir = tempfile::tempdir().expect("temp dir");
    let done = campaign(dir.path(), None, false);
    // 3 loss levels + 1 dead-link level + 1 reset level + 1 combined level, 3 protocols,
    // 2 seeds.
    assert_eq!(done.total, 36);
    assert_eq!(done.ran, 36);
    let text = std::fs::read_to_string(dir.path().join("runs.csv")).expect("runs.csv");
    let header = text.lines().next().expect("a header");
    assert_eq!(header, COLUMNS.join(","));
    let rows = sorted_rows(dir.path());
    assert_eq!(rows.len(), 36);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.split(',').count(), COLUMNS.len(), "{row}");
        assert!(row.starts_with(&format!("{i},")), "{row}");
    }
    assert!(rows.iter().any(|r| r.contains(",success,")));
    assert!(dir.path().join("summary.csv").is_file());
    // The combined level 0.5 scales every fault: loss 0.2, dead links 0.05, resets 0.01.
    let combined: Vec<&String> = rows.iter().filter(|r| r.contains(",combined,")).collect();
    assert_eq!(combined.len(), 6);
    for row in combined {
        let field = |name: &str| {
            let k = COLUMNS.iter().position(|c| *c == name).expect("column");
            row.split(',').nth(k).unwrap_or_default().to_string()
        };
        assert_eq!(field("value"), "0.5", "{row}");
        assert_eq!(field("loss"), "0.2", "{row}");
        assert_eq!(field("dead_link_p"), "0.05", "{row}");
        assert_eq!(field("reset_probability"), "0.01", "{row}");
        assert_eq!(field("reset_interval_ms"), "1000", "{row}");
    }
    let protocols: Vec<String> = rows
        .iter()
        .filter_map(|r| r.split(',').nth(3).map(str::to_string))
        .collect();
    assert!(protocols.iter().any(|p| p == "token-32"));
}

#[test]
fn a_resumed_campaign_gives_the_same_rows() {
    let whole = tempfile::tempdir().expect("temp dir");
    campaign(whole.path(), None, false);
    let parts = tempfile::tempdir().expect("temp dir");
    let first = campaign(parts.path(), Some(7), false);
    assert_eq!((first.already, first.ran), (0, 7));
    // An interruption in the middle of a line: the partial line is dropped and redone.
    let csv = parts.path().join("runs.csv");
    let mut text = std::fs::read_to_string(&csv).expect("runs.csv");
    text.truncate(text.len() - 10);
    std::fs::write(&csv, text).expect("truncate");
    let second = campaign(parts.path(), Some(5), false);
    assert_eq!((second.already, second.ran), (6, 5));
    let third = campaign(parts.path(), None, false);
    assert_eq!((third.already, third.ran), (11, 25));
    assert_eq!(sorted_rows(parts.path()), sorted_rows(whole.path()));
    let again = campaign(parts.path(), None, false);
    assert_eq!(again.ran, 0);
}

#[test]
fn rows_of_another_campaign_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    campaign(dir.path(), Some(2), false);
    let csv = dir.path().join("runs.csv");
    let text = std::fs::read_to_string(&csv).expect("runs.csv");
    std::fs::write(&csv, text.replacen(",atron,", ",ussr,", 1)).expect("write");
    let err = run(
        &options(dir.path(), None, false),
        &dynarole_robots::robots(),
        &mut Quiet,
    )
    .expect_err("must refuse");
    assert!(err.to_string().contains("other parameters"), "{err}");
}

#[test]
fn plots_are_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let done = campaign(dir.path(), None, true);
    for name in [
        "success-loss",
        "success-dead_link_p",
        "success-reset_probability",
        "success-combined",
        "completion-loss",
        "packets-loss",
    ] {
        for ext in ["svg", "png"] {
            let path = dir.path().join(format!("{name}.{ext}"));
            let bytes = std::fs::read(&path).expect("plot written");
            assert!(bytes.len() > 1000, "{}", path.display());
            assert!(done.files.contains(&path));
        }
    }
}

fn parse_error(text: &str) -> String {
    match CampaignFile::parse(text, Path::new(".")) {
        Ok(_) => panic!("accepted: {text}"),
        // The field first, as the CLI's title says it.
        Err(e) => format!("{}: {}", e.field, e.message),
    }
}

const MINIMAL: &str = r#"
file = "a.dr"
sequences = ["s"]
from = "a.json"
protocols = ["lattice"]
seeds = 1
"#;

#[test]
fn errors_name_the_field() {
    let bad_step = format!("{MINIMAL}[sweep]\nloss = {{ from = 0.0, to = 0.4, step = 0.0 }}\n");
    assert!(parse_error(&bad_step).starts_with("sweep.loss.step:"));
    let unknown =
        format!("{MINIMAL}colour = 1\n[sweep]\nloss = {{ from = 0.0, to = 0.4, step = 0.1 }}\n");
    assert!(parse_error(&unknown).contains("unknown field `colour`"));
    let no_interval =
        format!("{MINIMAL}[sweep]\nreset_probability = {{ from = 0.0, to = 0.1, step = 0.1 }}\n");
    assert!(parse_error(&no_interval).starts_with("sweep.reset_interval_ms:"));
    assert!(parse_error(MINIMAL).starts_with("sweep:"));
    let beyond = format!("{MINIMAL}[sweep]\nloss = {{ from = 0.5, to = 1.5, step = 0.5 }}\n");
    assert!(parse_error(&beyond).starts_with("sweep.loss:"));
    let both = format!("{MINIMAL}[scenario]\ntimeout_ms = 5\n[sweep]\nloss = {{ from = 0.0, to = 0.0, step = 1.0 }}\n");
    assert!(parse_error(&both).starts_with("scenario.timeout_ms:"));
    let half_combined =
        format!("{MINIMAL}[sweep]\ncombined = {{ from = 0.0, to = 1.0, step = 0.5 }}\ncombined_loss = 0.4\n");
    assert!(parse_error(&half_combined).starts_with("sweep.combined_dead_link_p:"));
    let token = MINIMAL.replace("\"lattice\"", "\"token-7\"");
    let token = format!("{token}[sweep]\nloss = {{ from = 0.0, to = 0.0, step = 1.0 }}\n");
    assert!(
        parse_error(&token).contains("token-7"),
        "{}",
        parse_error(&token)
    );
}

#[test]
fn ranges_include_their_end_and_round() {
    let r = dynarole_campaign::Range {
        from: 0.0,
        to: 0.4,
        step: 0.05,
    };
    let values = r.values("loss").expect("values");
    assert_eq!(values.len(), 9);
    assert_eq!(values.get(3), Some(&0.15));
    assert_eq!(values.last(), Some(&0.4));
}

#[test]
fn huge_campaigns_are_refused_before_planning() {
    let seeds = MINIMAL.replace("seeds = 1", "seeds = 4294967296");
    let seeds = format!("{seeds}[sweep]\nloss = {{ from = 0.0, to = 0.0, step = 1.0 }}\n");
    assert!(
        parse_error(&seeds).starts_with("seeds: expected 1 to 1000000"),
        "{}",
        parse_error(&seeds)
    );
    // Each factor is allowed; their product is not, and planning says so without building it.
    let product = MINIMAL.replace("seeds = 1", "seeds = 1000");
    let product = format!("{product}[sweep]\nloss = {{ from = 0.0, to = 1.0, step = 0.001 }}\n");
    let campaign = CampaignFile::parse(&product, Path::new(".")).expect("each field in range");
    let error = dynarole_campaign::plan(&campaign).expect_err("too many runs");
    assert_eq!(error.field, "seeds");
    assert!(
        error.message.contains("more than 1000000 runs"),
        "{}",
        error.message
    );
}

#[test]
fn a_plan_gives_each_run_from_its_index() {
    let text = MINIMAL.replace("seeds = 1", "seeds = 3");
    let text =
        format!("{text}first_seed = 7\n[sweep]\nloss = {{ from = 0.0, to = 0.2, step = 0.1 }}\n");
    let campaign = CampaignFile::parse(&text, Path::new(".")).expect("valid");
    let plan = dynarole_campaign::plan(&campaign).expect("small");
    assert_eq!(plan.len(), 9);
    let runs: Vec<(u64, f64, u64)> = plan.iter().map(|r| (r.index, r.value, r.seed)).collect();
    assert_eq!(runs[4], (4, 0.1, 8));
    assert_eq!(runs[8], (8, 0.2, 9));
    assert!(plan.get(9).is_none());
}

/// A path in a campaign file that does not resolve: the error names the field, the path as
/// written and the path it resolved to, and says what relative paths are relative to.
#[test]
fn unresolved_relative_paths_say_what_they_are_relative_to() {
    let root = tempfile::tempdir().expect("temp dir");
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/atron/examples");
    let text = std::fs::read_to_string(smoke()).expect("smoke.toml");
    let dir = root.path().join("campaigns");
    std::fs::create_dir(&dir).expect("a folder");
    let file = dir.join("moved.toml");
    let refused = |text: &str| {
        std::fs::write(&file, text).expect("the campaign");
        let options = Options {
            campaign: file.clone(),
            ..options(&root.path().join("out"), Some(1), false)
        };
        match run(&options, &dynarole_robots::robots(), &mut Quiet) {
            Err(dynarole_campaign::Error::Spec { error, .. }) => *error,
            Err(other) => panic!("not a field error: {other}"),
            Ok(_) => panic!("ran"),
        }
    };
    // Moved away from examples/: "../../robots/atron/examples/eight2car.dr" now points into
    // the temp dir.
    let error = refused(&text);
    assert_eq!(error.field, "file");
    assert!(
        error
            .message
            .starts_with("cannot read \"../../robots/atron/examples/eight2car.dr\": No such file"),
        "{}",
        error.message
    );
    let hint = error.hint.expect("a hint");
    let resolved = dir.join("../../robots/atron/examples/eight2car.dr");
    assert!(
        hint.contains("relative to the campaign file's directory")
            && hint.contains(&format!("resolved to {}", resolved.display())),
        "{hint}"
    );
    assert!(error.span.is_some(), "the field is located in the text");
    // The program found again (absolute), the expected configuration not.
    let program = examples.join("eight2car.dr");
    let from = examples.join("eight.json");
    let text = text
        .replace(
            "\"../../robots/atron/examples/eight2car.dr\"",
            &format!("{:?}", program.display().to_string()),
        )
        .replace(
            "\"../../robots/atron/examples/eight.json\"",
            &format!("{:?}", from.display().to_string()),
        );
    let error = refused(&text);
    assert_eq!(error.field, "expect");
    assert!(
        error
            .message
            .contains("\"../../robots/atron/examples/car.json\""),
        "{}",
        error.message
    );
}
