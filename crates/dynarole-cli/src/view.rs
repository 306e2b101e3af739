//! `dynarole view` and the `--record`, `--html` and `--poses-at` outputs of the commands that
//! make recordings: the recording as JSON, the self-contained viewer page, and every module's
//! pose at given times (what the browser tests compare the page with).

use crate::load::{self, Failure};
use dynarole_recording::{poses_at, Recording};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Where a command writes its recording.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct RecordArgs {
    /// Write the run's recording (JSON, docs/viewer.md) here.
    #[arg(long, value_name = "FILE.json")]
    pub record: Option<PathBuf>,
    /// Write the run as one self-contained viewer page (opens from disk, no network).
    #[arg(long, value_name = "FILE.html")]
    pub html: Option<PathBuf>,
    /// Print every module's pose at these times (milliseconds, comma-separated), as JSON.
    #[arg(long, value_name = "MS,...", value_delimiter = ',')]
    pub poses_at: Vec<f64>,
}

impl RecordArgs {
    /// Whether anything asks for a recording.
    pub fn wanted(&self) -> bool {
        self.record.is_some() || self.html.is_some() || !self.poses_at.is_empty()
    }

    /// Writes what was asked for.
    pub fn write(&self, recording: &Recording) -> Result<(), Failure> {
        if let Some(path) = &self.record {
            let text = serde_json::to_string(recording)
                .map_err(|e| Failure::Internal(format!("cannot serialise the recording: {e}")))?;
            write(path, &text)?;
        }
        if let Some(path) = &self.html {
            write_html(recording, path)?;
        }
        print_poses(recording, &self.poses_at)
    }
}

fn write(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))
}

fn write_html(recording: &Recording, path: &Path) -> Result<(), Failure> {
    let page = dynarole_viewer::html(recording).map_err(Failure::Internal)?;
    write(path, &page)?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// One JSON line per time: `{"time_ms": T, "modules": [{"name": N, "centre": [x, y, z]}]}`.
fn print_poses(recording: &Recording, times: &[f64]) -> Result<(), Failure> {
    for t in times {
        if !t.is_finite() || *t < 0.0 {
            return Err(Failure::Usage(format!(
                "--poses-at {t}: expected a time in milliseconds, 0 or more"
            )));
        }
        let poses = poses_at(recording, *t)
            .ok_or_else(|| Failure::Input("the recording has no keyframe".into()))?;
        let modules: Vec<serde_json::Value> = recording
            .modules
            .iter()
            .zip(&poses)
            .map(|(m, p)| serde_json::json!({ "name": m.name, "centre": p.centre }))
            .collect();
        println!(
            "{}",
            serde_json::json!({ "time_ms": t, "modules": modules })
        );
    }
    Ok(())
}

/// What `view` was asked to do.
pub struct ViewArgs<'a> {
    pub recording: &'a Path,
    pub output: Option<&'a PathBuf>,
    pub poses_at: &'a [f64],
    pub video: Option<&'a Path>,
    pub fps: u32,
    pub speed: f64,
}

pub fn run(args: &ViewArgs) -> Result<ExitCode, Failure> {
    if args.output.is_none() && args.poses_at.is_empty() && args.video.is_none() {
        return Err(Failure::Usage(
            "nothing to do: give -o FILE.html, --video FILE.mp4 or --poses-at".into(),
        ));
    }
    if args.fps == 0 || !(args.speed.is_finite() && args.speed > 0.0) {
        return Err(Failure::Usage(
            "--fps and --speed must be more than 0".into(),
        ));
    }
    let text = load::read_source(args.recording)?;
    let recording = Recording::from_json(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", args.recording.display())))?;
    if let Some(path) = args.output {
        write_html(&recording, path)?;
    }
    print_poses(&recording, args.poses_at)?;
    if let Some(out) = args.video {
        video(&recording, out, args)?;
        eprintln!("wrote {}", out.display());
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(unix)]
fn video(recording: &Recording, out: &Path, args: &ViewArgs) -> Result<(), Failure> {
    // The page goes to a scratch folder the browser reads it from.
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let dir = std::env::temp_dir().join(format!("dynarole-video-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir)
        .map_err(|e| Failure::Internal(format!("cannot create {}: {e}", dir.display())))?;
    let page = dir.join("page.html");
    let result = dynarole_viewer::html(recording)
        .map_err(Failure::Internal)
        .and_then(|text| write(&page, &text))
        .and_then(|()| {
            let options = crate::video::VideoOptions {
                fps: args.fps,
                speed: args.speed,
            };
            crate::video::render(recording, &page, out, options)
        });
    let _ = std::fs::remove_dir_all(&dir);
    result
}

#[cfg(not(unix))]
fn video(_: &Recording, _: &Path, _: &ViewArgs) -> Result<(), Failure> {
    Err(Failure::Usage("--video needs a Unix system".into()))
}

/// One step of a run on the model, with module names as in the configuration.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// The module does the statement's operation, start to end (replay).
    Operation(usize, String),
    /// The module issues the statement's operation (a counterexample's trail)...
    Issue(usize, String),
    /// ... and it completes physically.
    Done(usize, String),
    Reset(String),
    /// The module's copy of the shared protocol state is now this (the state panel).
    Copy(String, String),
    /// A property broken at this step: its name and what the trail explains.
    Violation(String, String),
}

/// The recording of a run on the model (no network): the steps in order, each operation
/// taking the simulator's default duration, so the page plays like a simulation.
pub struct ModelRun<'a> {
    pub kind: &'a str,
    pub title: &'a str,
    pub robot: &'a dynarole_core::robot::RobotApi,
    pub steps: &'a [Step],
    pub statements: &'a [dynarole_core::check::ResolvedStatement],
    pub start: &'a dynarole_world::Configuration,
    pub source: Option<dynarole_recording::Source<'a>>,
}

/// Pause between two steps of a model run (as a hand-over between modules would take).
const MODEL_GAP_MS: f64 = 100.0;

impl ModelRun<'_> {
    /// The recording, with `notes` (the verdict, the explanation) as its summary.
    pub fn record(&self, notes: Vec<String>) -> Result<Recording, Failure> {
        let texts: Vec<String> = self
            .statements
            .iter()
            .map(|s| s.describe(self.robot))
            .collect();
        let mut builder = dynarole_recording::Builder::new(
            self.kind,
            self.title,
            self.start,
            self.robot,
            self.statements,
            &texts,
            self.source,
        )
        .map_err(Failure::Input)?;
        let duration = |s: usize, turn: Option<&dynarole_recording::Turn>| -> f64 {
            nominal_ms(texts.get(s).map_or("", String::as_str), turn)
        };
        let view = dynarole_world::View::of(self.start);
        let index = |name: &str| {
            view.index(name)
                .ok_or_else(|| Failure::Internal(format!("no module {name} in the configuration")))
        };
        let mut now = 0.0;
        // Each module's last copy of the shared state, shown with each of its events.
        let mut states = vec!["-".to_string(); view.len()];
        // Per statement, when its operation was issued (a trail's completions follow later).
        let mut issued: Vec<(usize, f64, f64)> = Vec::new();
        for step in self.steps {
            match step {
                Step::Operation(s, module) => {
                    let (end, _) = builder.operation(now, index(module)?, *s, &duration);
                    now = end + MODEL_GAP_MS;
                }
                Step::Issue(s, module) => {
                    let label = format!("#{s} {}", texts.get(*s).map_or("", String::as_str));
                    let m = index(module)?;
                    builder.event(now, Some(m), "start", &states[m], &label);
                    let turn = builder.last_turn();
                    issued.retain(|(x, _, _)| x != s);
                    issued.push((*s, now, duration(*s, turn.as_ref())));
                    now += MODEL_GAP_MS;
                }
                Step::Done(s, module) => {
                    if let Some((_, at, length)) = issued.iter().find(|(x, _, _)| x == s) {
                        now = now.max(at + length);
                    }
                    let label = format!("#{s} {}", texts.get(*s).map_or("", String::as_str));
                    let m = index(module)?;
                    builder.event(now, Some(m), "done", &states[m], &label);
                    now += MODEL_GAP_MS;
                }
                Step::Reset(module) => {
                    let m = index(module)?;
                    builder.event(now, Some(m), "reset", &states[m], "");
                    now += MODEL_GAP_MS;
                }
                Step::Copy(module, state) => {
                    let m = index(module)?;
                    state.clone_into(&mut states[m]);
                    builder.event(now, Some(m), "copy", state, "");
                }
                Step::Violation(module, what) => {
                    let m = index(module)?;
                    builder.event(now, Some(m), "violation", &states[m], what);
                    now += MODEL_GAP_MS;
                }
            }
        }
        Ok(builder.finish(now, notes))
    }
}

/// The simulator's default duration of an operation (`dynarole_sim::Timing`).
fn nominal_ms(text: &str, turn: Option<&dynarole_recording::Turn>) -> f64 {
    let timing = dynarole_sim::Timing::default();
    let ms = match turn {
        Some(t) => timing.turn_ms((t.angle_deg.abs() / 90.0).round() as u64),
        None if text.contains(".retract(") => timing.retract_ms,
        None => timing.extend_ms,
    };
    ms as f64
}
