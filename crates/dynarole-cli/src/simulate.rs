//! `dynarole simulate`: the generated C on every module, over lossy infrared links, with the
//! faults of a scenario; exit 0 on success, 3 when the goal was not reached.

mod progress;

use crate::compile::add_routes;
use crate::load::{self, Failure};
use crate::world::read_configuration;
use clap::ValueEnum;
use dynarole_campaign::shell_word;
use dynarole_codegen::Choice;
use dynarole_recording::Source;
use dynarole_sim::{
    FirmwareReport, FirmwareSource, Outputs, Report, Run, Scenario, SimError, Simulator,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// What `simulate` was asked to do: its command line, parsed once.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// The `.dr` file holding the sequences.
    pub file: std::path::PathBuf,
    #[command(flatten)]
    pub run: crate::world::RunArgs,
    #[command(flatten)]
    pub options: crate::compile::ProtocolOptions,
    /// Faults, network and timing (TOML; see crates/dynarole-sim/SCENARIO.md).
    #[arg(long, value_name = "FILE")]
    pub scenario: Option<std::path::PathBuf>,
    /// Per-packet loss at the receiving connector (overrides the scenario's).
    #[arg(long, value_name = "P")]
    pub loss: Option<f64>,
    /// How modules are stepped (overrides the scenario's `stepping`).
    #[arg(long, value_name = "MODE", value_parser = crate::compile::choice::<dynarole_sim::Stepping>())]
    pub stepping: Option<dynarole_sim::Stepping>,
    /// Seed of every random draw (loss, faults, timing): the same seed and inputs give
    /// the same run, byte for byte.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Runs with seeds SEED, SEED+1, ... (at least 1).
    #[arg(long, default_value_t = 1, value_parser = crate::at_least_one)]
    pub repeat: u64,
    /// Write the event trace (fixed columns) here.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<std::path::PathBuf>,
    /// Print the report as JSON (one line per run).
    #[arg(long)]
    pub json: bool,
    /// Run every module's firmware on an emulated microcontroller instead of the C
    /// compiled for the host (docs/simulator.md; needs scripts/ensure-avr).
    #[arg(long, value_name = "MCU")]
    pub firmware: Option<FirmwareArg>,
    #[command(flatten)]
    pub record: crate::view::RecordArgs,
    #[command(flatten)]
    pub plugins: crate::load::PluginArgs,
}

/// `--firmware`: the microcontroller every module's firmware runs on, emulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FirmwareArg {
    /// An ATmega128 at 16 MHz (simavr) on the hemisphere board of runtime/avr, running its
    /// image
    Avr,
    /// The same MCU running the nesC component (`--target nesc`) compiled by nesC 1.4.0
    /// against runtime/nesc, with runtime/avr's platform (scripts/ensure-nesc builds nescc)
    AvrNesc,
}

pub fn run(args: &SimulateArgs) -> Result<ExitCode, Failure> {
    let failed = simulate_into(args, &mut Printed)?;
    if args.repeat > 1 && !args.json {
        println!(
            "{} of {} runs reached the goal",
            args.repeat - failed,
            args.repeat
        );
    }
    Ok(ExitCode::from(if failed == 0 { 0 } else { 3 }))
}

/// What is done with each run's report: printed by the command line (`Printed`), kept as
/// data by the library API (`api.rs`).
pub trait RunSink {
    /// Run `k` ended with `report` (and, on emulated firmware, `firmware`) after `wall`
    /// seconds.
    fn report(
        &mut self,
        args: &SimulateArgs,
        run: (&Report, Option<&FirmwareReport>),
        wall: f64,
        k: u64,
    ) -> Result<(), Failure>;
    /// Run with `seed` did not reach the goal.
    fn failed(&mut self, _args: &SimulateArgs, _seed: u64) {}
}

/// The command line's sink: each report on standard output, how to replay a failed run on
/// standard error.
struct Printed;

impl RunSink for Printed {
    fn report(
        &mut self,
        args: &SimulateArgs,
        (report, firmware): (&Report, Option<&FirmwareReport>),
        wall: f64,
        k: u64,
    ) -> Result<(), Failure> {
        output(args, report, firmware, wall, k)
    }

    fn failed(&mut self, args: &SimulateArgs, seed: u64) {
        eprintln!("replay with: {}", replay_command(args, seed));
    }
}

/// Runs `args` (every repeat), handing each report to `sink`; returns how many runs did not
/// reach the goal.
pub fn simulate_into(args: &SimulateArgs, sink: &mut dyn RunSink) -> Result<u64, Failure> {
    load::with_program(&args.file, &args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let names = load::select_sequences(program, &display, &args.run.sequences)?;
        let plans = crate::world::plans(program, &display, &names)?;
        let (scenario, scenario_text) = scenario(args)?;
        let start = read_configuration(&args.run.from)?;
        firmware_target(args, &start)?;
        let expect = args
            .run
            .expect
            .as_ref()
            .map(|p| read_configuration(p))
            .transpose()?;
        // A configuration of another robot is refused first, as `replay` refuses it: its
        // modules' labels would only give a misleading message.
        dynarole_replay::RobotWorld::new(start.clone(), &program.robot).map_err(Failure::Input)?;
        // A module the program names but the configuration lacks would never act: the run
        // would only time out. Refused here as `replay` refuses it, with the same message.
        if let Err(diagnostics) = dynarole_replay::assign_modules(program, &plans, &start) {
            return Err(Failure::checked(&display, source, diagnostics));
        }
        let mut options = args.options.compile_options(1, names.join(" + "))?;
        let routed = add_routes(&mut options, program, &plans, Some(&args.run.from))?;
        if let Err(diagnostics) = routed {
            return Err(Failure::checked(&display, source, diagnostics));
        }
        let simulator = match Simulator::new(program, &plans, &options) {
            Ok(s) => s,
            Err(SimError::Diagnostic(d)) => {
                return Err(Failure::checked(&display, source, vec![d]))
            }
            Err(e) => return Err(Failure::Input(e.to_string())),
        };
        if let (Some(path), Some(text)) = (args.scenario.as_ref(), scenario_text) {
            simulator
                .check_scenario(&scenario, &start)
                .map_err(|e| Failure::toml(path, text, e))?;
        }
        if args.record.wanted() && args.repeat > 1 {
            return Err(Failure::Usage(
                "--record, --html and --poses-at record one run: not with --repeat".into(),
            ));
        }
        let mode = crate::progress::ProgressMode::for_stderr().map_err(Failure::Usage)?;
        let progress = progress::RunProgress::start(mode, args.repeat.max(1), scenario.timeout_ms);
        let mut failed = 0u64;
        for k in 0..args.repeat.max(1) {
            let seed = args.seed.wrapping_add(k);
            let started = Instant::now();
            let run = Run {
                start: &start,
                expect: expect.as_ref(),
                scenario: &scenario,
                seed,
                trace: false,
            };
            let (report, firmware) = run_once(&simulator, &run, args, k, progress.clock())?;
            let wall = started.elapsed().as_secs_f64();
            progress.run_done();
            progress.suspend(|| sink.report(args, (&report, firmware.as_ref()), wall, k))?;
            if args.record.wanted() {
                let title = format!("{} ({}, seed {seed})", names.join(" + "), display);
                let recording = simulator
                    .recording(
                        &run,
                        &report,
                        &title,
                        Some(Source {
                            name: &display,
                            text: source,
                        }),
                    )
                    .map_err(|e| match e {
                        // A run too long to record, or a start the recording cannot take.
                        SimError::Input(m) => Failure::Input(m),
                        e => Failure::Internal(e.to_string()),
                    })?;
                args.record.write(&recording)?;
            }
            if !report.success {
                failed += 1;
                progress.suspend(|| sink.failed(args, seed));
            }
        }
        progress.finish();
        Ok(failed)
    })
}

/// `--firmware` runs on a board the robot's folder names as its firmware target
/// (`RobotKind::firmware_boards`: `avr` is runtime/avr's hemisphere board).
fn firmware_target(
    args: &SimulateArgs,
    start: &dynarole_world::Configuration,
) -> Result<(), Failure> {
    if args.firmware.is_none() {
        return Ok(());
    }
    let kind = start.kind();
    let boards = kind.firmware_boards();
    if boards.contains(&"avr") {
        return Ok(());
    }
    let has = if boards.is_empty() {
        "none".to_string()
    } else {
        boards.join(", ")
    };
    Err(Failure::Input(format!(
        "{}: robot `{}` has no firmware on the emulated hemisphere board (`avr`): its firmware \
         targets: {has}; run without --firmware",
        args.run.from.display(),
        kind.name()
    )))
}

/// Run `k` (seed `run.seed`) on the host or the emulated firmware, its trace streamed to
/// its file as it goes (`--trace`), recorded when `--record`/`--html` want it, its clock
/// shown by the progress line.
fn run_once(
    simulator: &Simulator,
    run: &Run,
    args: &SimulateArgs,
    k: u64,
    clock: std::sync::Arc<std::sync::atomic::AtomicU64>,
) -> Result<(Report, Option<FirmwareReport>), Failure> {
    let path = args.trace.as_ref().map(|p| trace_path(p, args.repeat, k));
    let cannot = |path: &Path, e: std::io::Error| {
        Failure::Input(format!("cannot write {}: {e}", path.display()))
    };
    let trace = match &path {
        Some(p) => Some(std::fs::File::create(p).map_err(|e| cannot(p, e))?),
        None => None,
    };
    let outputs = Outputs {
        trace: trace.map(|f| Box::new(f) as Box<dyn std::io::Write>),
        record: args.record.wanted(),
        clock: Some(clock),
        ..Outputs::default()
    };
    let result = match args.firmware {
        None => simulator.run_with(run, outputs).map(|r| (r, None)),
        Some(f) => {
            let source = match f {
                FirmwareArg::Avr => FirmwareSource::C,
                FirmwareArg::AvrNesc => FirmwareSource::Nesc,
            };
            (simulator.run_firmware_with(run, source, outputs)).map(|(r, fw)| (r, Some(fw)))
        }
    };
    result.map_err(|e| match (e, &path) {
        (SimError::Trace(e), Some(p)) => cannot(p, e),
        (e, _) => Failure::Input(e.to_string()),
    })
}

/// The trace file of run `k`: `PATH`, or `PATH.k` with `--repeat`.
fn trace_path(path: &Path, repeat: u64, k: u64) -> PathBuf {
    if repeat > 1 {
        PathBuf::from(format!("{}.{k}", path.display()))
    } else {
        path.to_path_buf()
    }
}

/// The scenario, and its text when it comes from a file (to show later errors in it).
fn scenario(args: &SimulateArgs) -> Result<(Scenario, Option<String>), Failure> {
    let (mut scenario, text) = match &args.scenario {
        Some(path) => {
            let text = load::read_source(path)?;
            let scenario =
                Scenario::from_toml_str(&text).map_err(|e| Failure::toml(path, text.clone(), e))?;
            (scenario, Some(text))
        }
        None => (Scenario::default(), None),
    };
    if let Some(loss) = args.loss {
        if !(0.0..=1.0).contains(&loss) {
            return Err(Failure::Usage(format!(
                "--loss {loss} is not a probability (0 to 1)"
            )));
        }
        scenario.network.loss = loss;
    }
    if let Some(stepping) = args.stepping {
        scenario.stepping = stepping;
    }
    Ok((scenario, text))
}

fn output(
    args: &SimulateArgs,
    report: &Report,
    firmware: Option<&FirmwareReport>,
    wall: f64,
    k: u64,
) -> Result<(), Failure> {
    if args.json {
        let value = report_json(report, firmware)?;
        let text = serde_json::to_string(&value).map_err(cannot_serialise)?;
        println!("{text}");
        return Ok(());
    }
    // The checks are explained once, where the first report names them.
    if k == 0 {
        print!("{}", report.summary_explained());
    } else {
        print!("{}", report.summary());
    }
    if let Some(d) = &report.difference {
        println!("  difference from the expected configuration:\n{d}");
    }
    if let Some(f) = firmware {
        print!("{}", firmware_table(f));
    }
    let speed = if wall > 0.0 {
        report.end_ms / 1000.0 / wall
    } else {
        0.0
    };
    // Emulated firmware runs slower than real time: two decimals there, whole numbers above.
    let digits = if speed < 10.0 { 2 } else { 0 };
    println!(
        "  simulated {:.3} s in {:.3} s of wall time ({speed:.digits$} x real time)",
        report.end_ms / 1000.0,
        wall
    );
    Ok(())
}

/// One run's report as `simulate --json` prints it (the firmware's measurements under
/// `firmware` when the run was on emulated chips).
pub fn report_json(
    report: &Report,
    firmware: Option<&FirmwareReport>,
) -> Result<serde_json::Value, Failure> {
    let mut value = serde_json::to_value(report).map_err(cannot_serialise)?;
    if let (Some(f), Some(object)) = (firmware, value.as_object_mut()) {
        let measured = serde_json::to_value(f).map_err(cannot_serialise)?;
        object.insert("firmware".into(), measured);
    }
    Ok(value)
}

/// A report that cannot be serialised (as before the library API: exit 1).
fn cannot_serialise(e: serde_json::Error) -> Failure {
    Failure::Input(format!("cannot serialise the report: {e}"))
}

/// The image's footprint and what the emulator measured on each module.
fn firmware_table(f: &FirmwareReport) -> String {
    let mean = |total: u64, n: u64| total.checked_div(n).unwrap_or(0);
    let mut out = format!(
        "  firmware (ATmega128, 16 MHz): flash {} bytes (text {} + data {}), static RAM {} bytes (data {} + bss {})\n",
        f.text + f.data,
        f.text,
        f.data,
        f.data + f.bss,
        f.data,
        f.bss
    );
    out.push_str("  module  stack (B)  steps  cycles/step (mean max)  receives  cycles/receive (mean max)  asleep\n");
    for m in &f.modules {
        let asleep = if m.cycles == 0 {
            0.0
        } else {
            100.0 * m.sleep_cycles as f64 / m.cycles as f64
        };
        out.push_str(&format!(
            "  {:<6} {:>10} {:>6} {:>12} {:>10} {:>9} {:>14} {:>10} {:>6.1}%\n",
            m.name,
            m.stack_bytes,
            m.steps,
            mean(m.step_cycles, m.steps),
            m.step_cycles_max,
            m.receives,
            mean(m.receive_cycles, m.receives),
            m.receive_cycles_max,
            asleep
        ));
    }
    out
}

/// The command line that replays one run exactly.
fn replay_command(args: &SimulateArgs, seed: u64) -> String {
    let mut parts = vec![
        "dynarole simulate".to_string(),
        shell_word(&args.file.display().to_string()),
    ];
    for s in &args.run.sequences {
        parts.push(format!("--sequence {}", shell_word(s)));
    }
    parts.push(format!(
        "--from {}",
        shell_word(&args.run.from.display().to_string())
    ));
    if let Some(e) = &args.run.expect {
        parts.push(format!("--expect {}", shell_word(&e.display().to_string())));
    }
    parts.extend(args.options.flags());
    if let Some(s) = &args.scenario {
        parts.push(format!(
            "--scenario {}",
            shell_word(&s.display().to_string())
        ));
    }
    if let Some(l) = args.loss {
        parts.push(format!("--loss {l}"));
    }
    if let Some(s) = args.stepping {
        parts.push(format!("--stepping {}", s.name()));
    }
    for p in &args.plugins.plugins {
        parts.push(format!("--plugin {}", shell_word(&p.display().to_string())));
    }
    if let Some(name) = args.firmware.and_then(|f| f.to_possible_value()) {
        parts.push(format!("--firmware {}", name.get_name()));
    }
    parts.push(format!("--seed {seed}"));
    parts.join(" ")
}
