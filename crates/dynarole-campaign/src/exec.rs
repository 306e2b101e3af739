//! Running the pending runs in parallel (rayon). A `Simulator` is not `Send`, so each worker
//! builds its own, one per protocol, on first use (the compiled C is cached on disk, so this
//! is cheap); each row goes to `runs.csv` as soon as its run finishes.

use crate::load::{compile_options, Inputs};
use crate::plan::PlannedRun;
use crate::progress::Progress;
use crate::results::{Row, Sink};
use crate::Error;
use dynarole_sim::{Run, SimError, Simulator};
use rayon::prelude::*;
use std::sync::Mutex;

/// One worker's simulators, by protocol (in the campaign's order).
struct Worker<'a> {
    inputs: &'a Inputs<'a>,
    simulators: Vec<Option<Simulator>>,
}

impl<'a> Worker<'a> {
    fn new(inputs: &'a Inputs<'a>) -> Worker<'a> {
        let simulators = inputs.campaign.protocols.iter().map(|_| None).collect();
        Worker { inputs, simulators }
    }

    fn simulator(&mut self, run: &PlannedRun) -> Result<&Simulator, Error> {
        let campaign = &self.inputs.campaign;
        let k = campaign
            .protocols
            .iter()
            .position(|p| *p == run.protocol)
            .ok_or_else(|| Error::Sim(format!("protocol {} not planned", run.protocol.name())))?;
        let slot = self
            .simulators
            .get_mut(k)
            .ok_or_else(|| Error::Sim("no simulator slot".into()))?;
        if slot.is_none() {
            *slot = Some(simulator(self.inputs, run.protocol)?);
        }
        slot.as_ref()
            .ok_or_else(|| Error::Sim("no simulator".into()))
    }

    fn run(&mut self, run: &PlannedRun) -> Result<Row, Error> {
        let inputs = self.inputs;
        let scenario = run.scenario(&inputs.campaign.scenario);
        let report = self
            .simulator(run)?
            .run(&Run {
                start: inputs.start,
                expect: inputs.expect,
                scenario: &scenario,
                seed: run.seed,
                trace: false,
            })
            .map_err(|e| Error::Sim(format!("run {}: {e}", run.index)))?;
        Ok(Row::new(
            run,
            inputs.preset.name,
            scenario.timeout_ms,
            &report,
        ))
    }
}

/// A simulator for `protocol`.
pub fn simulator(inputs: &Inputs, protocol: dynarole_codegen::Variant) -> Result<Simulator, Error> {
    let mut options = compile_options(inputs.campaign, protocol);
    if options.protocol.needs_routes() {
        let routes = dynarole_replay::token_routes(&inputs.program, &inputs.plans, inputs.start)
            .map_err(|diagnostics| Error::Diagnostics {
                path: inputs.campaign.file.clone(),
                source: inputs.source.to_string(),
                diagnostics,
            })?;
        options.routes = Some(routes);
    }
    Simulator::new(&inputs.program, &inputs.plans, &options).map_err(|e| match e {
        SimError::Diagnostic(d) => Error::Diagnostics {
            path: inputs.campaign.file.clone(),
            source: inputs.source.to_string(),
            diagnostics: vec![d],
        },
        other => Error::Sim(format!("{}: {other}", protocol.name())),
    })
}

/// Builds every protocol's C once, before the parallel phase, so that the workers find it in
/// the cache and a build error is reported once.
pub fn prepare(inputs: &Inputs) -> Result<(), Error> {
    let preset = inputs.preset;
    for &protocol in &inputs.campaign.protocols {
        simulator(inputs, protocol)?
            .build_directory(preset)
            .map_err(|e| Error::Sim(format!("{}: {e}", protocol.name())))?;
    }
    Ok(())
}

/// Runs `pending` on `jobs` threads (all cores when `None`), appending each row to `sink` and
/// telling `progress` of them as `label`, `before` of `total` runs recorded earlier; returns
/// the new rows (in completion order).
pub fn run_all(
    inputs: &Inputs<'_>,
    pending: &[PlannedRun],
    sink: Sink,
    jobs: Option<usize>,
    progress: &mut dyn Progress,
    (label, before, total): (&str, u64, u64),
) -> Result<Vec<Row>, Error> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.unwrap_or(0))
        .build()
        .map_err(|e| Error::Sim(format!("cannot start the worker threads: {e}")))?;
    progress.started(label, before, total, "runs");
    let shared = Mutex::new((sink, Vec::with_capacity(pending.len())));
    let ticks: &dyn Progress = progress;
    let outcome = pool.install(|| {
        pending.par_iter().try_for_each_init(
            || Worker::new(inputs),
            |worker, run| {
                if ticks.stop_requested() {
                    return Err(Error::Interrupted);
                }
                let row = worker.run(run)?;
                let mut guard = shared.lock().unwrap_or_else(|e| e.into_inner());
                guard.0.write(&row)?;
                guard.1.push(row);
                ticks.advanced();
                Ok::<(), Error>(())
            },
        )
    });
    // Finished on an error too, so that the bar is gone before the error is printed.
    progress.finished();
    outcome?;
    Ok(shared.into_inner().unwrap_or_else(|e| e.into_inner()).1)
}
