//! dynarole-sim: a deterministic discrete-event simulator that runs the generated C of a
//! compiled sequence on every module (compiled for the host, with the simulator as its HAL),
//! over lossy infrared links, with faults; it checks S1, S2, S3 at every step and compares the
//! final configuration with the expected one. See `README.md` and `SCENARIO.md`.
//!
//! ```text
//! let sim = Simulator::new(&program, &plans, &compile_options)?;
//! let report = sim.run(&Run { start: &config, expect: Some(&car), scenario: &scenario,
//!                             seed: 7, trace: true })?;
//! ```

mod build;
mod critical;
mod describe;
mod engine;
mod estimate;
mod event;
mod ffi;
mod firmware;
mod links;
mod model_recording;
mod network;
mod ops;
mod packet;
mod queue;
mod record;
mod recorded;
mod report;
mod scenario;
mod sequence;
mod state;
mod stops;
mod trace;
mod unended;
mod wake;

pub use build::{cache_entries, cache_root};
pub use critical::CriticalPath;
pub use estimate::{choose_form, form_makespan, makespan, shortest, Estimated};
pub use firmware::{FirmwareReport, FirmwareSource, ModuleFirmware};
pub use model_recording::{replay_steps, ModelRecording, ModelRecordingError};
pub use recorded::{Recorded, MAX_RECORDED, RECORDED_PACKETS};
pub use report::{Counters, ModuleReport, Outcome, Refusal, Report, Stop, Violation};
pub use scenario::{
    default_durations, Block, Dead, Durations, FailureByKind, Faults, Foreign, Network,
    OperationFailure, Power, Preset, PresetName, RandomResets, Reset, Scenario, ScenarioError,
    Stepping, Stuck, Timing, MAX_TIMEOUT_MS, USSR, USSR_TIMING,
};
pub use trace::Outputs;

use build::Loaded;
use dynarole_codegen::{generate_c, nesc_files, CompileOptions, Protocol};
use dynarole_core::diagnostic::Diagnostic;
use dynarole_core::expand::Plan;
use dynarole_core::Program;
use dynarole_replay::RobotWorld;
use dynarole_world::{Configuration, RobotModel};
use sequence::Sequence;
use state::State;
use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;
use std::sync::Arc;

/// Why a simulation could not run (as opposed to a run that did not reach its goal).
#[derive(Debug)]
pub enum SimError {
    /// The sequence cannot be compiled for the protocol (rendered at its source location).
    Diagnostic(Diagnostic),
    /// The C did not build or load.
    Build(String),
    /// A configuration or scenario that does not fit the sequence.
    Input(String),
    /// The trace file could not be written (`Outputs::trace`).
    Trace(std::io::Error),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Diagnostic(d) => write!(f, "{:?}", d.kind),
            SimError::Build(m) | SimError::Input(m) => f.write_str(m),
            SimError::Trace(e) => write!(f, "cannot write the trace: {e}"),
        }
    }
}

impl std::error::Error for SimError {}

/// One run's inputs besides the compiled sequence.
#[derive(Clone, Copy, Debug)]
pub struct Run<'a> {
    pub start: &'a Configuration,
    pub expect: Option<&'a Configuration>,
    pub scenario: &'a Scenario,
    pub seed: u64,
    /// Keep the event trace (`Report::trace`).
    pub trace: bool,
}

/// One run on robot models rather than configuration files: for a robot that has no file
/// format (one defined outside the built-in ones), or a start built in memory.
#[derive(Clone, Copy, Debug)]
pub struct ModelRun<'a> {
    pub start: &'a dyn RobotModel,
    pub expect: Option<&'a dyn RobotModel>,
    pub scenario: &'a Scenario,
    pub seed: u64,
    /// Keep the event trace (`Report::trace`).
    pub trace: bool,
}

/// What a run keeps and writes of its trace: the lines in memory (`Run::trace`, which also
/// records them) and the outputs.
struct Traced {
    keep: bool,
    outputs: Outputs,
}

/// What a run's end is compared with.
#[derive(Clone, Copy)]
enum Expected<'a> {
    Configuration(&'a Configuration),
    Model(&'a dyn RobotModel),
}

/// A run's two references for its end: where it started (`Report::final_matches_start`) and
/// the goal, if one is given.
#[derive(Clone, Copy)]
struct Ends<'a> {
    start: Expected<'a>,
    expect: Option<Expected<'a>>,
}

/// The network preset `scenario` names for the robot of `world` (`PresetName::resolve`).
pub fn preset_of(world: &RobotWorld, scenario: &Scenario) -> Result<Preset, String> {
    scenario.network.preset.resolve(world.network_presets())
}

/// A compiled sequence, ready to run any number of times (builds are cached per preset).
pub struct Simulator {
    sequence: Arc<Sequence>,
    files: Vec<(String, String)>,
    /// The nesC component around `files` (`--target nesc`), for `--firmware avr-nesc`.
    nesc: Vec<(String, String)>,
    protocol: Protocol,
    packet_bytes: usize,
    loaded: RefCell<Vec<(Preset, Rc<Loaded>)>>,
}

impl Simulator {
    /// Lowers `plans` (run in turn) and generates their C for `options.protocol`.
    pub fn new(
        program: &Program,
        plans: &[Plan],
        options: &CompileOptions,
    ) -> Result<Simulator, SimError> {
        let ir = dynarole_core::driver::lower(program, plans, options.protocol.shape())
            .map_err(SimError::Diagnostic)?;
        let generated =
            generate_c(&ir, &program.robot, options).map_err(|e| SimError::Diagnostic(e.into()))?;
        let resolved = plans
            .iter()
            .flat_map(|p| p.statements().into_iter().cloned())
            .collect();
        let mut sequence = Sequence::new(program.robot.clone(), ir, resolved);
        sequence.execution = options.execution;
        Ok(Simulator {
            sequence: Arc::new(sequence),
            files: generated.files,
            nesc: nesc_files(options),
            protocol: options.protocol,
            packet_bytes: generated.packet_bytes,
            loaded: RefCell::new(Vec::new()),
        })
    }

    /// Bytes of one state packet on the wire.
    pub fn packet_bytes(&self) -> usize {
        self.packet_bytes
    }

    pub fn statements(&self) -> usize {
        self.sequence.len()
    }

    /// The durations `timing` names for the sequence's robot (`Timing::durations`): an
    /// unknown preset is an error at `timing.preset`.
    pub fn durations(&self, timing: &Timing) -> Result<Durations, ScenarioError> {
        timing.durations(&self.sequence.robot)
    }

    /// The mechanical critical path with `durations` (`Simulator::durations`): the heaviest
    /// chain of dependencies, a lower bound of any run's completion time (`critical.rs`).
    pub fn critical_path(&self, durations: &Durations) -> CriticalPath {
        critical::critical_path(&self.sequence, durations)
    }

    /// `critical_path` with each module's statements run one at a time, in source order
    /// (`critical.rs`): the bound of a runtime that runs one operation per module at a time
    /// (the lattice runtime with `DR_CONF_LATTICE_BATCH` 1, and before batches).
    pub fn critical_path_one_at_a_time(&self, durations: &Durations) -> CriticalPath {
        critical::one_at_a_time(&self.sequence, durations)
    }

    /// Builds (or finds in the cache) the C for `preset` and loads it.
    fn library(&self, preset: Preset) -> Result<Rc<Loaded>, SimError> {
        if let Some((_, l)) = self.loaded.borrow().iter().find(|(p, _)| *p == preset) {
            return Ok(Rc::clone(l));
        }
        let defines = vec![format!(
            "-DDR_CONF_BROADCAST_JITTER_MS={}",
            preset.jitter_ms
        )];
        let loaded =
            Rc::new(build::build_and_load(&self.files, &defines).map_err(SimError::Build)?);
        self.loaded.borrow_mut().push((preset, Rc::clone(&loaded)));
        Ok(loaded)
    }

    /// Bytes of one module's C context (`dr_sim_module_size()`; the engine rounds it up to
    /// whole 8-byte words), building the C for `preset` if needed.
    pub fn module_context_bytes(&self, preset: Preset) -> Result<usize, SimError> {
        Ok(self.library(preset)?.entry.module_size)
    }

    /// Where the build for `preset` lives (building it if needed), and whether it was found
    /// in the cache.
    pub fn build_directory(&self, preset: Preset) -> Result<(std::path::PathBuf, bool), SimError> {
        let library = self.library(preset)?;
        Ok((library.directory.clone(), library.cached))
    }

    /// Every module and connector `scenario` names exists in the configuration `start` (the
    /// check `run` makes, for callers that report it against the scenario's text).
    pub fn check_scenario(
        &self,
        scenario: &Scenario,
        start: &Configuration,
    ) -> Result<(), ScenarioError> {
        let world = RobotWorld::new(start.clone(), &self.sequence.robot)
            .map_err(|e| ScenarioError::new("", e))?;
        self.check_scenario_on(&world, scenario)
    }

    fn check_scenario_on(
        &self,
        world: &RobotWorld,
        scenario: &Scenario,
    ) -> Result<(), ScenarioError> {
        preset_of(world, scenario).map_err(|e| ScenarioError::new("network.preset", e))?;
        self.durations(&scenario.timing)?;
        scenario.check_parts(&self.sequence.robot)?;
        let view = world.view();
        scenario.check_modules(|name| view.index(name).is_some(), view.connectors())
    }

    /// One run: deterministic in the inputs and the seed.
    pub fn run(&self, run: &Run) -> Result<Report, SimError> {
        self.run_with(run, Outputs::default())
    }

    /// One run that also writes `outputs` as it goes (the trace file, the recording, the
    /// clock): the same run and report as [`Simulator::run`].
    pub fn run_with(&self, run: &Run, outputs: Outputs) -> Result<Report, SimError> {
        let world = self.world_for(run)?;
        let ends = Ends {
            start: Expected::Configuration(run.start),
            expect: run.expect.map(Expected::Configuration),
        };
        let traced = Traced {
            keep: run.trace,
            outputs,
        };
        self.run_world(world, ends, run.scenario, run.seed, traced)
    }

    /// One run from a robot model: deterministic in the inputs and the seed.
    pub fn run_model(&self, run: &ModelRun) -> Result<Report, SimError> {
        let world = RobotWorld::from_model(run.start.clone_model(), &self.sequence.robot)
            .map_err(SimError::Input)?;
        let world = self.checked(world, run.scenario)?;
        let ends = Ends {
            start: Expected::Model(run.start),
            expect: run.expect.map(Expected::Model),
        };
        let traced = Traced {
            keep: run.trace,
            outputs: Outputs::default(),
        };
        self.run_world(world, ends, run.scenario, run.seed, traced)
    }

    /// A run from `world` (checked against the scenario), its end compared with `expect`.
    fn run_world(
        &self,
        world: RobotWorld,
        ends: Ends,
        scenario: &Scenario,
        seed: u64,
        traced: Traced,
    ) -> Result<Report, SimError> {
        let preset = preset_of(&world, scenario).map_err(SimError::Input)?;
        let durations = self.run_durations(scenario)?;
        let library = self.library(preset)?;
        let foreign_frames = if scenario.foreign.is_empty() {
            Vec::new()
        } else {
            let how = (scenario, preset, durations);
            self.other_robots_frames(world.clone(), how, seed, library.entry)?
        };
        let mut state = State::new(
            Arc::clone(&self.sequence),
            (world, preset, durations),
            scenario.clone(),
            seed,
            traced.keep,
        );
        state.set_outputs(traced.outputs);
        state.foreign_frames = foreign_frames;
        let mut finished = engine::run(library.entry, state).map_err(SimError::Build)?;
        finished.state.flush_trace().map_err(SimError::Trace)?;
        Ok(self.report_against(ends, scenario, seed, finished))
    }

    /// The start configuration's world, once the scenario is checked against it.
    fn world_for(&self, run: &Run) -> Result<RobotWorld, SimError> {
        let world =
            RobotWorld::new(run.start.clone(), &self.sequence.robot).map_err(SimError::Input)?;
        self.checked(world, run.scenario)
    }

    /// The durations of a run of `scenario` (checked with the scenario before any run).
    fn run_durations(&self, scenario: &Scenario) -> Result<Durations, SimError> {
        (self.durations(&scenario.timing)).map_err(|e| SimError::Input(format!("scenario: {e}")))
    }

    /// `world` once it is within the simulator's limits and the scenario is checked against
    /// it.
    fn checked(&self, world: RobotWorld, scenario: &Scenario) -> Result<RobotWorld, SimError> {
        let view = world.view();
        if view.len() > links::MAX_MODULES || usize::from(view.connectors()) > packet::QUEUES {
            return Err(SimError::Input(format!(
                "{} modules of {} connectors: the simulator runs at most {} modules of at most {} connectors",
                view.len(),
                view.connectors(),
                links::MAX_MODULES,
                packet::QUEUES
            )));
        }
        scenario
            .check()
            .map_err(|e| SimError::Input(e.to_string()))?;
        self.check_scenario_on(&world, scenario)
            .map_err(|e| SimError::Input(format!("scenario: {e}")))?;
        Ok(world)
    }

    /// The second robot of `Scenario::foreign`: the same program from the same start, run
    /// without faults (same network preset and timing), and the last frame each of its
    /// modules broadcast (the end, once it finished).
    fn other_robots_frames(
        &self,
        world: RobotWorld,
        (scenario, preset, durations): (&Scenario, Preset, Durations),
        seed: u64,
        entry: build::Entry,
    ) -> Result<Vec<Option<Vec<u8>>>, SimError> {
        let scenario = Scenario {
            timeout_ms: scenario.timeout_ms,
            network: Network {
                preset: scenario.network.preset.clone(),
                ..Network::default()
            },
            timing: scenario.timing.clone(),
            ..Scenario::default()
        };
        let world = (world, preset, durations);
        let mut state = State::new(Arc::clone(&self.sequence), world, scenario, seed, false);
        state.last_frames = Some(vec![None; state.n_modules()]);
        let finished = engine::run(entry, state).map_err(SimError::Build)?;
        Ok(finished.state.last_frames.unwrap_or_default())
    }

    /// The report of a run from a configuration file.
    fn report(&self, run: &Run, finished: engine::Finished) -> Report {
        let ends = Ends {
            start: Expected::Configuration(run.start),
            expect: run.expect.map(Expected::Configuration),
        };
        self.report_against(ends, run.scenario, run.seed, finished)
    }

    /// The report of a finished run, its end compared with `expect`; the trace is kept when
    /// the run kept one.
    fn report_against(
        &self,
        ends: Ends,
        scenario: &Scenario,
        seed: u64,
        finished: engine::Finished,
    ) -> Report {
        let engine::Finished {
            mut state,
            addresses,
        } = finished;
        let ms = |t: u64| t as f64 / 1000.0;
        let recorded = state.record;
        // A model is compared before the world is moved out; a configuration after, on
        // the moved value (no copy of a large robot's configuration).
        let model_difference = match ends.expect {
            Some(Expected::Model(expected)) => Some(state.world.model().difference(expected)),
            _ => None,
        };
        let model_at_start = match ends.start {
            Expected::Model(start) => Some(state.world.model().difference(start).is_none()),
            Expected::Configuration(_) => None,
        };
        let statements_done = state.phys.iter().filter(|p| p.done.is_some()).count();
        let view = state.view();
        let modules = state
            .modules
            .iter()
            .zip(&addresses)
            .enumerate()
            .map(|(k, (m, address))| ModuleReport {
                name: view.name(k),
                id: m.id,
                address: *address,
                packets_sent: m.stats.sent,
                packets_received: m.stats.received,
                packets_dropped: m.stats.dropped,
                operations: m.stats.operations,
                resets: m.stats.resets,
                power_cycles: m.stats.power_cycles,
                finished_ms: m.finished_at.map(ms),
            })
            .collect();
        let finished: Vec<bool> = state
            .modules
            .iter()
            .map(|m| m.finished_at.is_some())
            .collect();
        // Only a run some module finished says who did not: with none, the timeout says it.
        let never_ended = if state.first_finished.is_some() {
            unended::never_ended(view, &finished)
        } else {
            Vec::new()
        };
        let all_finished_ms = state
            .all_finished()
            .then(|| state.modules.iter().filter_map(|m| m.finished_at).max())
            .flatten()
            .map(ms);
        let mut report = Report {
            success: false,
            failures: Vec::new(),
            seed,
            protocol: self.protocol.name().into(),
            preset: state.preset.name.into(),
            completion_ms: state.first_finished.map(ms),
            all_finished_ms,
            never_ended,
            end_ms: ms(state.now),
            statements: self.sequence.len(),
            statements_done,
            counters: state.counters.clone(),
            outcome: Outcome::Timeout,
            final_matches_start: false,
            stopped: state.stops(),
            violations: std::mem::take(&mut state.violations),
            refusals: std::mem::take(&mut state.refusals),
            modules,
            synchronous_spread_ms: synchronous_spread(&self.sequence, &state.phys).map(ms),
            configuration_matches: None,
            difference: None,
            trace: state.trace.take().and_then(trace::Trace::into_lines),
            recorded: recorded.then(|| std::mem::take(&mut state.recorded)),
            // Moved out of the world last: the rest of the state is freed with it.
            final_configuration: state.into_configuration(),
        };
        let difference = match (ends.expect, model_difference) {
            (Some(Expected::Configuration(expected)), _) => {
                Some(end_difference(&report.final_configuration, expected))
            }
            (_, difference) => difference,
        };
        report.final_matches_start = match ends.start {
            Expected::Configuration(start) => {
                end_difference(&report.final_configuration, start).is_none()
            }
            Expected::Model(_) => model_at_start.unwrap_or(false),
        };
        if let Some(difference) = difference {
            report.configuration_matches = Some(difference.is_none());
            report.difference = difference;
        }
        report.failures = failures(&report, scenario.timeout_ms);
        report.success = report.failures.is_empty();
        report.outcome = Outcome::of(&report);
        report
    }
}

/// How the run's end differs from `reference` (`None`: it is the same).
fn end_difference(end: &Option<Configuration>, reference: &Configuration) -> Option<String> {
    match end {
        Some(end) => dynarole_world::compare_with_expected(end, reference)
            .err()
            .map(|d| d.to_string()),
        None => Some("the robot model has no configuration format".into()),
    }
}

fn failures(report: &Report, timeout_ms: u64) -> Vec<String> {
    let mut out = Vec::new();
    if report.completion_ms.is_none() {
        out.push(format!(
            "timeout: no module declared the end within {:.3} s",
            timeout_ms as f64 / 1000.0
        ));
    }
    if report.statements_done < report.statements {
        out.push(format!(
            "{} of {} statements never completed",
            report.statements - report.statements_done,
            report.statements
        ));
    }
    if !report.stopped.is_empty() {
        let modules: Vec<&str> = report.stopped.iter().map(|s| s.module.as_str()).collect();
        out.push(format!(
            "stopped: an operation failed and the failure policy gave up on {}",
            modules.join(", ")
        ));
    }
    if !report.violations.is_empty() {
        let clashes = match report.count("clash") {
            0 => String::new(),
            n => format!(", clash {n}"),
        };
        out.push(format!(
            "{} violations (S1 {}, S2 {}, S3 {}{clashes})",
            report.violations.len(),
            report.count("S1"),
            report.count("S2"),
            report.count("S3")
        ));
    }
    if report.configuration_matches == Some(false) {
        out.push("the final configuration is not the expected one".into());
    }
    out
}

/// The most the first starts of one synchronous group's statements were apart (in the
/// simulator's time unit), over the groups all of whose statements started; `None` when the
/// sequence has no synchronous group.
fn synchronous_spread(seq: &Sequence, phys: &[state::Phys]) -> Option<u64> {
    let mut spread = None;
    for s in 0..seq.len() {
        let Some(group) = seq.synchronous(s).filter(|g| g.start == s) else {
            continue;
        };
        let starts: Option<Vec<u64>> = group.map(|k| phys.get(k).and_then(|p| p.started)).collect();
        let widest = starts.map_or(0, |t| {
            t.iter().max().unwrap_or(&0) - t.iter().min().unwrap_or(&0)
        });
        spread = Some(spread.unwrap_or(0).max(widest));
    }
    spread
}
