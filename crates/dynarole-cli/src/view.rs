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
    let dir = load::scratch_dir("video");
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

/// A model run that could not be recorded: bad input, or a step the caller got wrong.
pub fn model_failure(error: dynarole_sim::ModelRecordingError) -> Failure {
    match error {
        dynarole_sim::ModelRecordingError::Input(m) => Failure::Input(m),
        dynarole_sim::ModelRecordingError::Internal(m) => Failure::Internal(m),
    }
}
