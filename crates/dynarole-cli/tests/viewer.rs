//! The viewer page in a real headless Chromium (Debian's, installed by
//! `scripts/ensure-chromium`): a simulation under faults written with `--html`, opened from
//! disk with `#probe=T1,T2,...` so that the page seeks to each time as its scrubber does and
//! writes what it shows into its DOM, which the browser dumps. Checked: module colours on the
//! canvas, every module's position against the simulator's `--poses-at`, the statement
//! highlight and the state panel against the trace, the fault marker where the scenario put
//! it, operation faults and a failure policy's stop marked where they happened, the legend
//! listing the trace event vocabulary, and no request of any kind.

mod common;

use common::{dynarole, repo_root, text};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const PROGRAM: &str = "robots/atron/examples/eight2car.dr";
/// A reset of M4 at 4.5 s while it connects (the paper's Fig. 8 left).
const SCENARIO: &str = "examples/scenarios/fig8-reset-connecting.toml";
const RESET_MS: f64 = 4500.0;

/// Runs `scripts/ensure-SCRIPT ARGS`, which installs `what` when missing; false (the test
/// says why it skips) when that is impossible on this machine.
fn installed(script: &str, args: &[&str], what: &str) -> bool {
    let path = format!("scripts/ensure-{script}");
    let status = Command::new(repo_root().join(&path)).args(args).status();
    let ok = matches!(status, Ok(s) if s.success());
    if !ok {
        let call = [path.as_str()]
            .iter()
            .chain(args)
            .copied()
            .collect::<Vec<_>>();
        eprintln!(
            "SKIPPED: {what} could not be installed ({} failed)",
            call.join(" ")
        );
    }
    ok
}

/// Debian's chromium, installed when missing; `None` when that is impossible here.
fn chromium() -> Option<PathBuf> {
    installed("chromium", &[], "chromium").then(|| PathBuf::from("chromium"))
}

/// The window of every headless run (the rest: the flags the video export uses too).
const WINDOW: &str = "--window-size=1200,800";

/// The browser run headless in the window of every run.
fn headless(browser: &Path) -> Command {
    let mut command = Command::new(browser);
    command
        .args(dynarole_cli::video::HEADLESS_FLAGS)
        .arg(WINDOW);
    command
}

/// Times as the page's `#probe=` and `--poses-at` take them: milliseconds, comma-separated.
fn time_list(times: &[f64]) -> String {
    let list: Vec<String> = times.iter().map(|t| format!("{t}")).collect();
    list.join(",")
}

/// Opens `page` at the given times and returns what its probe wrote.
fn probe(browser: &Path, page: &Path, times: &[f64]) -> Value {
    let url = format!("file://{}#probe={}", page.display(), time_list(times));
    let out = headless(browser)
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .expect("chromium runs");
    let dom = text(&out.stdout);
    let start = dom
        .find("<pre id=\"probe\">")
        .unwrap_or_else(|| panic!("no probe in the page's DOM; stderr: {}", text(&out.stderr)))
        + "<pre id=\"probe\">".len();
    let end = dom[start..].find("</pre>").expect("the probe ends") + start;
    let json = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    serde_json::from_str(&json).expect("the probe is JSON")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// A recorded run: its page, its recording and the poses the command printed at `times`.
struct Simulated {
    page: PathBuf,
    recording: Value,
    poses: Vec<Value>,
}

/// Runs `dynarole ARGS --html --record [--poses-at TIMES]` and reads what it wrote.
fn recorded(dir: &Path, command: &[&str], times: &[f64], expected_exit: i32) -> Simulated {
    let page = dir.join("run.html");
    let record = dir.join("run.json");
    let joined = time_list(times);
    let mut args = command.to_vec();
    args.extend([
        "--html",
        page.to_str().expect("utf-8 path"),
        "--record",
        record.to_str().expect("utf-8 path"),
    ]);
    if !times.is_empty() {
        args.extend(["--poses-at", &joined]);
    }
    let out = dynarole(&args);
    assert_eq!(
        out.status.code(),
        Some(expected_exit),
        "{}",
        text(&out.stderr)
    );
    let stdout = text(&out.stdout);
    let poses = stdout
        .lines()
        .filter(|l| l.starts_with("{\"modules\""))
        .map(|l| serde_json::from_str(l).expect("a pose line"))
        .collect();
    let recording = serde_json::from_str(&std::fs::read_to_string(&record).expect("recording"))
        .expect("recording JSON");
    Simulated {
        page,
        recording,
        poses,
    }
}

fn simulate(dir: &Path, times: &[f64]) -> Simulated {
    let command = [
        "simulate",
        PROGRAM,
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
        "--expect",
        "robots/atron/examples/car.json",
        "--scenario",
        SCENARIO,
        "--seed",
        "3",
    ];
    recorded(dir, &command, times, 0)
}

/// Times to look at: the start, the middle of the first turns (modules in motion), the
/// reset, and late in the run.
fn interesting_times() -> Vec<f64> {
    // The middles of turns are read from a first recording of the same run.
    let dir = scratch("times");
    let first = simulate(&dir, &[0.0]);
    let mut times = vec![0.0, RESET_MS + 10.0];
    let turns = first.recording["motions"]
        .as_array()
        .expect("motions")
        .iter()
        .filter(|m| !m["path"].is_null() && m["outcome"] == "done")
        .take(3);
    for m in turns {
        let (a, b) = (m["start_ms"].as_f64(), m["end_ms"].as_f64());
        if let (Some(a), Some(b)) = (a, b) {
            times.push(a + (b - a) * 0.37);
        }
    }
    times.push(first.recording["end_ms"].as_f64().expect("end") - 1.0);
    times
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("viewer")
        .join(name);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

#[test]
fn the_page_shows_the_simulated_world_at_every_time() {
    let Some(browser) = chromium() else { return };
    let times = interesting_times();
    let run = simulate(&scratch("sim"), &times);
    let shown = check_page(&browser, &run, &times, PROGRAM);
    let samples = shown["samples"].as_array().expect("samples");
    let end = run.recording["end_ms"].as_f64().expect("end");
    check_marker(&samples[0], "reset", RESET_MS, "M4", end);
}

/// Opens the page at `times` and checks what it shows against the command's poses and the
/// recording; returns what the page reported.
fn check_page(browser: &Path, run: &Simulated, times: &[f64], program: &str) -> Value {
    let shown = probe(browser, &run.page, times);
    // Nothing was requested: every resource the page loaded, and every blocked one.
    assert_eq!(
        shown["resources"],
        Value::Array(vec![]),
        "the page made requests"
    );
    assert_eq!(shown["violations"], Value::Array(vec![]));
    check_legend(&shown["legend"]);
    // Every part's colour (the recording's drawing) is on the canvas.
    let colours = &shown["colours"];
    let total = colours["pixels"].as_f64().expect("pixels");
    let parts = colours["parts"].as_array().expect("a count per part");
    assert!(!parts.is_empty(), "no part drawn: {colours}");
    for (k, n) in parts.iter().enumerate() {
        let n = n.as_f64().expect("count");
        assert!(n > total * 0.002, "too few pixels of part {k}: {colours}");
    }
    let samples = shown["samples"].as_array().expect("samples");
    assert_eq!(samples.len(), times.len());
    let mut moved = false;
    for ((sample, expected), t) in samples.iter().zip(&run.poses).zip(times) {
        assert_eq!(sample["time_ms"].as_f64(), Some(*t));
        let modules = expected["modules"].as_array().expect("modules");
        let positions = sample["positions"].as_array().expect("positions");
        assert_eq!(positions.len(), modules.len());
        for (p, m) in positions.iter().zip(modules) {
            let (page, sim) = (numbers(p), numbers(&m["centre"]));
            for (a, b) in page.iter().zip(&sim) {
                assert!(
                    (a - b).abs() < 1e-6,
                    "at {t} ms {}: page {page:?}, simulator {sim:?}",
                    m["name"]
                );
            }
            moved |= sim.iter().any(|x| x.fract().abs() > 1e-3);
        }
        check_highlight(&run.recording, sample, *t, program);
        check_state_panel(&run.recording, sample, *t);
    }
    assert!(moved, "no sample caught a module between lattice sites");
    shown
}

/// The legend lists every marker kind with the events that place it, and every bar colour
/// with the event that ends it, in the vocabulary's colours.
fn check_legend(legend: &Value) {
    use dynarole_recording::{Operation, EVENTS, MARKS};
    let entries = legend.as_array().expect("a legend");
    // A marker and a bar may share a name (`refused`): an entry is its kind and its name.
    let entry = |kind: &str, name: &str| {
        entries
            .iter()
            .find(|e| e["kind"] == kind && e["name"] == name)
            .unwrap_or_else(|| panic!("no {kind} {name} in the legend {legend}"))
    };
    for mark in MARKS {
        let events: Vec<&str> = EVENTS
            .iter()
            .filter(|e| e.mark == Some(mark.kind))
            .map(|e| e.name)
            .collect();
        let shown = entry("marker", mark.name);
        assert_eq!(shown["colour"], mark.colour);
        assert_eq!(shown["events"], serde_json::json!(events), "{}", mark.name);
        let text = shown["text"].as_str().expect("text");
        assert!(events.iter().all(|e| text.contains(e)), "{text}");
    }
    for e in EVENTS {
        if let Operation::Ends(colour) = e.operation {
            assert_eq!(entry("bar", e.name)["colour"], colour);
            assert_eq!(entry("bar", e.name)["events"], serde_json::json!([e.name]));
        }
    }
}

/// The highlighted statements are those running at `t`, shown with their source text.
fn check_highlight(recording: &Value, sample: &Value, t: f64, program: &str) {
    let mut running: Vec<u64> = recording["motions"]
        .as_array()
        .expect("motions")
        .iter()
        .filter(|m| {
            let (a, b) = (m["start_ms"].as_f64(), m["end_ms"].as_f64());
            // An operation still running when the run stopped has no end.
            let open = m["outcome"] == "running";
            a <= Some(t) && (Some(t) < b || open)
        })
        .filter_map(|m| m["statement"].as_u64())
        .collect();
    running.sort_unstable();
    let mut shown: Vec<u64> = sample["highlighted"]["statements"]
        .as_array()
        .expect("statements")
        .iter()
        .filter_map(Value::as_u64)
        .collect();
    shown.sort_unstable();
    assert_eq!(shown, running, "highlight at {t} ms");
    let source = std::fs::read_to_string(repo_root().join(program)).expect("source");
    for s in &running {
        let st = &recording["statements"][*s as usize];
        let (a, b) = (st["start"].as_u64(), st["end"].as_u64());
        let written = &source[a.expect("start") as usize..b.expect("end") as usize];
        let texts = sample["highlighted"]["text"].as_array().expect("texts");
        assert!(
            texts.iter().any(|x| x == written),
            "{written} not highlighted at {t} ms"
        );
    }
}

/// Each module's row shows the protocol state of its last trace line at or before `t`.
fn check_state_panel(recording: &Value, sample: &Value, t: f64) {
    let events = recording["events"].as_array().expect("events");
    for (m, row) in sample["state"].as_array().expect("rows").iter().enumerate() {
        let last = events
            .iter()
            .rev()
            .find(|e| e["module"].as_u64() == Some(m as u64) && e["time_ms"].as_f64() <= Some(t));
        let expected = last.map_or("-", |e| e["state"].as_str().expect("state"));
        assert_eq!(
            row["state"].as_str(),
            Some(expected),
            "state of module {m} at {t} ms"
        );
    }
}

/// A marker of `kind` at `at_ms` naming `module`, drawn at its place on the timeline.
fn check_marker(sample: &Value, kind: &str, at_ms: f64, module: &str, end: f64) {
    let markers = sample["markers"].as_array().expect("markers");
    let marker = markers
        .iter()
        .find(|m| m["kind"] == kind)
        .unwrap_or_else(|| panic!("no {kind} marker in {markers:?}"));
    let at = marker["time_ms"].as_f64().expect("time");
    assert!((at - at_ms).abs() < 1.0, "{kind} marked at {at} ms");
    let label = marker["label"].as_str().expect("label");
    assert!(label.contains(module), "{label}");
    let fraction = marker["fraction"].as_f64().expect("fraction");
    assert!(
        (fraction - at / end).abs() < 0.01,
        "drawn at {fraction} of the timeline"
    );
}

/// Runs `command` (which exits with `expected_exit`) twice, in scratch folders named after
/// `name`: once to learn its [`sample_times`], then with the poses at them.
fn recorded_at_samples(name: &str, command: &[&str], expected_exit: i32) -> (Simulated, Vec<f64>) {
    let first = recorded(
        &scratch(&format!("{name}-times")),
        command,
        &[],
        expected_exit,
    );
    let times = sample_times(&first.recording);
    let run = recorded(&scratch(name), command, &times, expected_exit);
    (run, times)
}

/// Samples every `step` milliseconds of a recording, plus the middle of each turn.
fn sample_times(recording: &Value) -> Vec<f64> {
    let end = recording["end_ms"].as_f64().expect("end");
    let mut times: Vec<f64> = (0..8).map(|k| end * f64::from(k) / 8.0).collect();
    for m in recording["motions"].as_array().expect("motions") {
        if !m["path"].is_null() && m["outcome"] == "done" {
            let (a, b) = (m["start_ms"].as_f64(), m["end_ms"].as_f64());
            if let (Some(a), Some(b)) = (a, b) {
                times.push(a + (b - a) * 0.61);
            }
        }
    }
    // Whole microseconds: serde_json reads some longer decimals back one bit off, and the
    // page's times are compared exactly.
    times
        .iter()
        .map(|t| (t * 1000.0).round() / 1000.0)
        .collect()
}

#[test]
fn a_replay_on_the_model_plays_in_the_page() {
    let Some(browser) = chromium() else { return };
    let command = [
        "replay",
        PROGRAM,
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
        "--expect",
        "robots/atron/examples/car.json",
    ];
    let (run, times) = recorded_at_samples("replay", &command, 0);
    assert_eq!(run.recording["kind"], "replay");
    check_page(&browser, &run, &times, PROGRAM);
}

/// An M-TRAN run: the blocks turn smoothly as the world model plans each joint turn, and
/// the page's modules mid-turn are where `--poses-at` puts them.
#[test]
fn an_mtran_simulation_turns_smoothly_in_the_page() {
    let Some(browser) = chromium() else { return };
    let program = "robots/mtran/examples/move_module.dr";
    let command = [
        "simulate",
        program,
        "--sequence",
        "left2right",
        "--from",
        "robots/mtran/examples/mtran-snake4.json",
        "--expect",
        "robots/mtran/examples/mtran-snake4-moved.json",
    ];
    let (run, times) = recorded_at_samples("mtran", &command, 0);
    assert_eq!(run.recording["robot"], "mtran");
    let turns = run.recording["motions"]
        .as_array()
        .expect("motions")
        .iter()
        .filter(|m| !m["path"].is_null())
        .count();
    assert_eq!(turns, 8, "every joint turn of left2right has a motion");
    check_page(&browser, &run, &times, program);
}

/// Legs of every kind: a recording whose first two turns are rewritten as a slide then the
/// turn, and as a corner slide (two translations), is shown by the page where `view
/// --poses-at` (the Rust reader, `dynarole_world::Motion`) puts every module mid-motion.
#[test]
fn the_page_moves_what_a_path_carries_along_legs_of_every_kind() {
    let Some(browser) = chromium() else { return };
    let dir = scratch("legs");
    let mut recording = simulate(&dir, &[]).recording;
    let motions = recording["motions"].as_array_mut().expect("motions");
    let moving: Vec<usize> = (0..motions.len())
        .filter(|&k| !motions[k]["path"].is_null() && motions[k]["outcome"] == "done")
        .filter(|&k| motions[k]["end_ms"].as_f64() > motions[k]["start_ms"].as_f64())
        .take(2)
        .collect();
    assert_eq!(moving.len(), 2, "two turns to rewrite");
    let turn = motions[moving[0]]["path"]["legs"][0].clone();
    motions[moving[0]]["path"]["legs"] =
        serde_json::json!([{"translate": {"by": [0.5, 0.0, 0.25]}}, turn]);
    motions[moving[1]]["path"]["legs"] = serde_json::json!([
        {"translate": {"by": [0.0, 1.0, 0.0]}},
        {"translate": {"by": [0.0, 0.0, -1.0]}}
    ]);
    let mut times = Vec::new();
    for k in &moving {
        let (a, b) = (
            motions[*k]["start_ms"].as_f64(),
            motions[*k]["end_ms"].as_f64(),
        );
        let (a, b) = (a.expect("start"), b.expect("end"));
        // Whole microseconds, so that the page's times compare exactly.
        let at = |f: f64| ((a + (b - a) * f) * 1000.0).round() / 1000.0;
        times.extend([at(0.2), at(0.5), at(0.8)]);
    }
    let file = dir.join("legs.json");
    let written = serde_json::to_string(&recording).expect("serialises");
    std::fs::write(&file, written).expect("written");
    let page = dir.join("legs.html");
    let (file_arg, page_arg) = (file.to_str().expect("utf-8"), page.to_str().expect("utf-8"));
    let joined = time_list(&times);
    let out = dynarole(&["view", file_arg, "-o", page_arg, "--poses-at", &joined]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let expected: Vec<Value> = text(&out.stdout)
        .lines()
        .filter(|l| l.starts_with("{\"modules\""))
        .map(|l| serde_json::from_str(l).expect("a pose line"))
        .collect();
    assert_eq!(expected.len(), times.len());
    let shown = probe(&browser, &page, &times);
    let samples = shown["samples"].as_array().expect("samples");
    let mut off_lattice = false;
    for ((sample, expected), t) in samples.iter().zip(&expected).zip(&times) {
        let modules = expected["modules"].as_array().expect("modules");
        let positions = sample["positions"].as_array().expect("positions");
        for (p, m) in positions.iter().zip(modules) {
            let (page, reader) = (numbers(p), numbers(&m["centre"]));
            let apart = page.iter().zip(&reader).any(|(a, b)| (a - b).abs() > 1e-6);
            assert!(
                !apart,
                "at {t} ms {}: page {page:?}, reader {reader:?}",
                m["name"]
            );
            off_lattice |= reader.iter().any(|x| (x * 4.0).fract().abs() > 1e-3);
        }
    }
    assert!(
        off_lattice,
        "no sample caught a module part-way along a leg"
    );
}

/// The paper protocol's race on `A & B; C;`: the trail's steps on the robot, and S1 named
/// where it breaks.
#[test]
fn a_counterexample_plays_in_the_page_with_the_broken_property() {
    let Some(browser) = chromium() else { return };
    if !installed("spin", &[], "spin") {
        return;
    }
    let program = "robots/atron/examples/verify/ab_c.dr";
    let command = [
        "verify",
        program,
        "--from",
        "robots/atron/examples/verify/line3.json",
        "--protocol",
        "paper",
    ];
    let (run, times) = recorded_at_samples("verify", &command, 1);
    assert_eq!(run.recording["kind"], "counterexample");
    let summary = run.recording["summary"][0].as_str().expect("summary");
    assert_eq!(summary, "VIOLATED: S1");
    let shown = check_page(&browser, &run, &times, program);
    let violation = run.recording["markers"]
        .as_array()
        .expect("markers")
        .iter()
        .find(|m| m["kind"] == "violation")
        .expect("a violation marker");
    let at = violation["time_ms"].as_f64().expect("time");
    let end = run.recording["end_ms"].as_f64().expect("end");
    let samples = shown["samples"].as_array().expect("samples");
    check_marker(&samples[0], "violation", at, "S1", end);
    check_marker(&samples[0], "violation", at, "M2", end);
    // The state panel shows the modules' copies of the shared state from the trail.
    let latest = samples
        .iter()
        .max_by(|a, b| {
            a["time_ms"]
                .as_f64()
                .partial_cmp(&b["time_ms"].as_f64())
                .expect("times")
        })
        .expect("a sample");
    let rows = latest["state"].as_array().expect("rows");
    let copies = rows
        .iter()
        .filter(|r| r["state"].as_str().is_some_and(|x| x.starts_with("state ")))
        .count();
    assert!(copies >= 2, "{rows:?}");
}

/// The README's picture: eight2car mid-run in the page, as the browser shows it. Written to
/// `docs/pictures/viewer-eight2car.png` when `DYNAROLE_UPDATE_PICTURES` is set.
#[test]
fn screenshot_of_eight2car_mid_run() {
    let Some(browser) = chromium() else { return };
    let run = simulate(&scratch("screenshot"), &[]);
    let shot = scratch("screenshot").join("eight2car.png");
    let _ = std::fs::remove_file(&shot);
    let url = format!("file://{}#t=16000", run.page.display());
    let out = headless(&browser)
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .expect("chromium runs");
    let png =
        std::fs::read(&shot).unwrap_or_else(|_| panic!("no screenshot: {}", text(&out.stderr)));
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 20_000,
        "not a picture of a scene"
    );
    if std::env::var_os("DYNAROLE_UPDATE_PICTURES").is_some() {
        let to = repo_root().join("docs/pictures/viewer-eight2car.png");
        std::fs::create_dir_all(to.parent().expect("a folder")).expect("docs/pictures");
        std::fs::write(&to, &png).expect("write the picture");
    }
}

/// `view --video`: one frame per 1/fps video second (speed run seconds each), encoded.
#[test]
fn a_recording_becomes_a_video() {
    if chromium().is_none() {
        return;
    }
    if !installed("chromium", &["--ffmpeg"], "ffmpeg") {
        return;
    }
    let dir = scratch("video");
    let command = [
        "replay",
        PROGRAM,
        "--sequence",
        "eight2car",
        "--from",
        "robots/atron/examples/eight.json",
    ];
    let run = recorded(&dir, &command, &[], 0);
    let video = dir.join("run.mp4");
    let _ = std::fs::remove_file(&video);
    let record = dir.join("run.json");
    let out = dynarole(&[
        "view",
        record.to_str().expect("utf-8 path"),
        "--video",
        video.to_str().expect("utf-8 path"),
        "--fps",
        "2",
        "--speed",
        "8",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=codec_name,nb_read_frames",
            "-of",
            "csv=p=0",
        ])
        .arg(&video)
        .output()
        .expect("ffprobe runs");
    let end = run.recording["end_ms"].as_f64().expect("end");
    let frames = (end / 4000.0).ceil() as u64 + 1;
    assert_eq!(text(&probe.stdout).trim(), format!("h264,{frames}"));
}

/// Operation faults on the timeline: M4's connector 0 stuck from the start (its extend, the
/// fourth statement, fails and `--on-failure stop` gives up at once) and M5 dead at 12 s,
/// after the stop (dead at 2 s, it kept the news of M3's turn from M4, which never started).
/// The page marks the failure and the stop on M4 and the death on M5 where they happened,
/// and the recording keeps the failed attempt as a motion of outcome `failed`.
#[test]
fn operation_faults_and_a_stop_are_marked_on_the_timeline() {
    let Some(browser) = chromium() else { return };
    let dir = scratch("operation-faults");
    let scenario = dir.join("faults.toml");
    let faults = "timeout_ms = 20000\n[[stuck]]\nmodule = \"M4\"\npart = \"Connector[0]\"\n\
                  from_ms = 0\n[[dead]]\nmodule = \"M5\"\nat_ms = 12000\n";
    std::fs::write(&scenario, faults).expect("the scenario is written");
    let command = [
        "simulate",
        PROGRAM,
        "--from",
        "robots/atron/examples/eight.json",
        "--expect",
        "robots/atron/examples/car.json",
        "--scenario",
        scenario.to_str().expect("utf-8 path"),
        "--on-failure",
        "stop",
        "--seed",
        "1",
    ];
    let (run, times) = recorded_at_samples("operation-faults", &command, 3);
    let failed = (run.recording["motions"].as_array().expect("motions").iter())
        .find(|m| m["outcome"] == "failed")
        .expect("a failed motion");
    let failed_at = failed["end_ms"].as_f64().expect("its end");
    let shown = check_page(&browser, &run, &times, PROGRAM);
    let end = run.recording["end_ms"].as_f64().expect("end");
    let sample = &shown["samples"].as_array().expect("samples")[0];
    check_marker(sample, "power", 12000.0, "M5", end);
    let markers = sample["markers"].as_array().expect("markers");
    let refused: Vec<&Value> = (markers.iter())
        .filter(|m| m["kind"] == "refused")
        .collect();
    let labels: Vec<&str> = (refused.iter())
        .map(|m| m["label"].as_str().expect("label"))
        .collect();
    for event in ["failed on M4", "stopped on M4"] {
        assert!(
            labels.iter().any(|l| l.starts_with(event)),
            "{event}: {labels:?}"
        );
    }
    for marker in refused {
        let at = marker["time_ms"].as_f64().expect("time");
        assert!(
            (at - failed_at).abs() < 1.0,
            "marked at {at}, failed at {failed_at}"
        );
    }
}
