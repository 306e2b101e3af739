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

    /// Writes what was asked for; the poses are worked out first, so that a time the
    /// recording cannot answer writes nothing.
    pub fn write(&self, recording: &Recording) -> Result<(), Failure> {
        let poses = pose_lines(recording, &self.poses_at)?;
        if let Some(path) = &self.record {
            let text = serde_json::to_string(recording)
                .map_err(|e| Failure::Internal(format!("cannot serialise the recording: {e}")))?;
            within_the_recording_limit(text.len())?;
            write(path, &text)?;
        }
        if let Some(path) = &self.html {
            write_html(recording, path)?;
        }
        poses.iter().for_each(|line| println!("{line}"));
        Ok(())
    }
}

/// A recording larger than `view` reads is refused before it is written.
fn within_the_recording_limit(bytes: usize) -> Result<(), Failure> {
    let limit = dynarole_input::MAX_RECORDING_BYTES;
    if bytes as u64 > limit {
        return Err(Failure::Input(format!(
            "the recording would be {} MiB, over the {} MiB that `dynarole view` reads: record a \
             shorter run",
            bytes >> 20,
            limit >> 20
        )));
    }
    Ok(())
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
fn pose_lines(recording: &Recording, times: &[f64]) -> Result<Vec<String>, Failure> {
    times.iter().map(|&t| pose_line(recording, t)).collect()
}

fn pose_line(recording: &Recording, t: f64) -> Result<String, Failure> {
    if !t.is_finite() || t < 0.0 {
        return Err(Failure::Usage(format!(
            "--poses-at {t}: expected a time in milliseconds, 0 or more"
        )));
    }
    let first = recording.keyframes.first().map_or(0.0, |k| k.time_ms);
    let poses = poses_at(recording, t).ok_or_else(|| {
        Failure::Input(format!(
            "--poses-at {t}: the recording's first keyframe is at {first} ms; expected a time \
             from {first} ms"
        ))
    })?;
    let modules: Vec<serde_json::Value> = recording
        .modules
        .iter()
        .zip(&poses)
        .map(|(m, p)| serde_json::json!({ "name": m.name, "centre": p.centre }))
        .collect();
    Ok(serde_json::json!({ "time_ms": t, "modules": modules }).to_string())
}

/// What `view` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct ViewArgs {
    /// The recording (JSON, written by `--record`).
    pub recording: std::path::PathBuf,
    /// The page to write.
    #[arg(short = 'o', long = "output", value_name = "FILE.html")]
    pub output: Option<std::path::PathBuf>,
    /// Print every module's pose at these times (milliseconds, comma-separated), as JSON.
    #[arg(long, value_name = "MS,...", value_delimiter = ',')]
    pub poses_at: Vec<f64>,
    /// Render the run as a video (MP4; headless chromium and ffmpeg).
    #[arg(long, value_name = "FILE.mp4")]
    pub video: Option<std::path::PathBuf>,
    /// Frames per second of the video.
    #[arg(long, default_value_t = 25)]
    pub fps: u32,
    /// Run seconds per video second.
    #[arg(long, default_value_t = 1.0)]
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
    let text = dynarole_input::read_recording(&args.recording)
        .map_err(|e| Failure::Input(e.to_string()))?;
    let recording = Recording::from_json(&text)
        .map_err(|e| Failure::Input(format!("{}: {e}", args.recording.display())))?;
    let poses = pose_lines(&recording, &args.poses_at)?;
    if let Some(path) = &args.output {
        write_html(&recording, path)?;
    }
    poses.iter().for_each(|line| println!("{line}"));
    if let Some(out) = &args.video {
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
