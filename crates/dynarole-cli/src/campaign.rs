//! `dynarole campaign`: a sweep of simulated runs described by a TOML file, run in parallel,
//! written to `DIR/runs.csv` (resumable), `DIR/summary.csv` and plots
//! (`crates/dynarole-campaign/README.md`).

use crate::load::Failure;
use crate::render;
use dynarole_campaign::{Done, Error, Options, ProgressMode};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// What `campaign` was asked to do.
pub struct CampaignArgs<'a> {
    pub file: &'a Path,
    pub out_dir: Option<&'a PathBuf>,
    pub max_runs: Option<u64>,
    pub jobs: Option<usize>,
    pub no_plots: bool,
}

pub fn run(args: &CampaignArgs) -> Result<ExitCode, Failure> {
    let out_dir = match args.out_dir {
        Some(d) => d.clone(),
        None => default_out_dir(args.file),
    };
    let options = Options {
        campaign: args.file.to_path_buf(),
        out_dir,
        max_runs: args.max_runs,
        jobs: args.jobs,
        progress: ProgressMode::for_stderr().map_err(Failure::Usage)?,
        plots: !args.no_plots,
    };
    match dynarole_campaign::run(&options) {
        Ok(done) => {
            print_done(&done);
            Ok(ExitCode::SUCCESS)
        }
        Err(Error::Diagnostics {
            path,
            source,
            diagnostics,
        }) => {
            render::diagnostics(&path.display().to_string(), &source, &diagnostics);
            Ok(ExitCode::from(1))
        }
        Err(Error::Spec { path, text, error }) => Err(Failure::toml(&path, text, *error)),
        Err(e) => Err(Failure::Input(e.to_string())),
    }
}

/// `out/NAME` for `NAME.toml`: generated files stay under `out/`, which git ignores.
fn default_out_dir(file: &Path) -> PathBuf {
    let stem = file
        .file_stem()
        .map_or("campaign".into(), |s| s.to_string_lossy().into_owned());
    Path::new("out").join(stem)
}

fn print_done(done: &Done) {
    println!(
        "{} runs: {} recorded before, {} run now in {:.1} s, {} still to do",
        done.total,
        done.already,
        done.ran,
        done.wall_seconds,
        done.total - done.already - done.ran
    );
    println!(
        "{:<18} {:>8} {:<8} {:>5} {:>8} {:>15} {:>12} {:>9}",
        "axis", "value", "protocol", "runs", "success", "95 % interval", "median (s)", "packets"
    );
    for s in &done.summaries {
        let median = s
            .median_completion_ms
            .map_or("-".into(), |t| format!("{:.3}", t / 1000.0));
        println!(
            "{:<18} {:>8} {:<8} {:>5} {:>7.1}% {:>15} {:>12} {:>9.0}",
            s.axis,
            s.value,
            s.protocol,
            s.runs,
            100.0 * s.success_rate,
            format!(
                "{:.1}-{:.1}%",
                100.0 * s.success_low,
                100.0 * s.success_high
            ),
            median,
            s.mean_packets_sent
        );
    }
    for f in &done.files {
        println!("wrote {}", f.display());
    }
}
