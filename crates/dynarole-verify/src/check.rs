//! The checks of a built model: S1-S3 and L on the full model (for a large robot, bounded
//! searches first; bitstate when the exhaustive search does not fit), or module by module on
//! the compositional models; the first violation shortened, replayed and explained.

use crate::explain::{tell, Context, Counterexample};
use crate::model::{Built, Models, AUTO_FULL_MODULES};
use crate::report::{CheckName, Entry, Header, Observer, Report, Verdict};
use crate::spin::{self, Check, Limits, PanResult, Progress};
use crate::trail::{parse_events, Event};
use crate::VerifyError;
use dynarole_codegen::{LivenessGraph, Model, Setting};
use std::path::Path;

/// How the checks run.
#[derive(Clone, Debug)]
pub struct VerifyOptions {
    /// Memory for each search (MB); beyond it, bitstate.
    pub memory_mb: u64,
    /// Time for each search (seconds); beyond it, bitstate.
    pub time_s: u64,
    /// Bitstate hashing from the start (a partial search, never a proof).
    pub bitstate: bool,
    /// S1, S2 and S3 only (not L).
    pub safety_only: bool,
}

/// The source a counterexample is told against: its name in messages and its text.
#[derive(Clone, Copy)]
pub struct Source<'a> {
    pub path: &'a str,
    pub text: &'a str,
}

/// The bounds of the searches tried first (steps after `init`), each run only when the last
/// met its bound without a violation; each gets a quarter of the time limit.
pub const BOUNDED_STEPS: [u64; 3] = [50, 100, 200];

/// Checks `built` with spin in `dir` (which must exist; spin's files are left there), telling
/// `observer` each entry as it comes and the progress of the tools.
pub fn verify(
    built: &Built,
    header: Header,
    options: &VerifyOptions,
    source: Source,
    dir: &Path,
    observer: &mut dyn Observer,
) -> Result<Report, VerifyError> {
    spin::check_tools()?;
    observer.header(&header);
    let mut run = Run {
        built,
        options,
        source,
        observer,
        entries: Vec::new(),
    };
    let verdicts = match &built.models {
        Models::Full(model) => {
            let how = How {
                module: None,
                bounded_first: built.topology.modules.len() > AUTO_FULL_MODULES,
            };
            run.check_model(dir, model, &run.checks(), how)?
        }
        Models::Compositional {
            per_module,
            liveness,
        } => run.check_each_module(dir, per_module, liveness)?,
    };
    let verdict = if verdicts.contains(&Verdict::Violated) {
        Verdict::Violated
    } else if verdicts.iter().all(|v| *v == Verdict::Verified) {
        Verdict::Verified
    } else {
        Verdict::Inconclusive
    };
    Ok(Report {
        header,
        entries: run.entries,
        verdict,
    })
}

/// The header of `built` checked with `options` on `configuration`.
pub fn header(built: &Built, options: &crate::BuildOptions, configuration: &str) -> Header {
    let stages = built.ir.statements.len() + 1;
    let links_throughout = built
        .topology
        .links
        .iter()
        .filter(|l| l.fair_stages.len() == stages)
        .count();
    let o = &options.compile;
    Header {
        name: built.name.clone(),
        configuration: configuration.to_string(),
        protocol: o.describe(),
        statements: built.ir.statements.len(),
        modules: built.topology.modules.len(),
        links: built.topology.links.len(),
        links_throughout,
        resets: options.resets,
        reset_only: options.reset_only.clone(),
        late: match built.models {
            Models::Full(_) => Some(options.late),
            Models::Compositional { .. } => None,
        },
        epochs: o.protocol.takes(Setting::Epochs).then_some(o.runs().max(1)),
        fault: options.fault.is_some(),
    }
}

/// How one model is checked.
#[derive(Clone, Copy)]
struct How<'a> {
    /// The module a compositional model is for (`None`: the full model).
    module: Option<&'a str>,
    /// Look for a short violation first (bounded searches, [`BOUNDED_STEPS`]): the full model
    /// of a robot larger than [`AUTO_FULL_MODULES`] modules, whose exhaustive search runs deep
    /// before it backtracks to a violation a few steps from the start.
    bounded_first: bool,
}

/// A verification under way: what it checks, and the entries found so far.
struct Run<'a> {
    built: &'a Built,
    options: &'a VerifyOptions,
    source: Source<'a>,
    observer: &'a mut dyn Observer,
    entries: Vec<Entry>,
}

impl Run<'_> {
    fn tell(&mut self, entry: Entry) {
        self.observer.entry(&entry);
        self.entries.push(entry);
    }

    fn checks(&self) -> Vec<Check> {
        if self.options.safety_only {
            vec![Check::Safety]
        } else {
            vec![Check::Safety, Check::Liveness]
        }
    }

    fn limits(&self) -> Limits {
        Limits {
            memory_mb: self.options.memory_mb,
            time_s: self.options.time_s,
            bitstate: self.options.bitstate,
            shortest: false,
            depth: None,
        }
    }

    /// The compositional method: the modules one at a time (each model in its own
    /// directory), stopping at the first violation; L only where the links that surely exist
    /// carry what it needs.
    fn check_each_module(
        &mut self,
        dir: &Path,
        per_module: &[Model],
        liveness: &LivenessGraph,
    ) -> Result<Vec<Verdict>, VerifyError> {
        self.tell(Entry::Compositional);
        let mut verdicts = Vec::new();
        let mut checks = vec![Check::Safety];
        if !self.options.safety_only {
            let stuck = liveness.stuck_statements();
            let deaf = liveness.deaf_modules();
            if stuck.is_empty() && deaf.is_empty() {
                self.tell(Entry::LivenessLinks);
                checks.push(Check::Liveness);
            } else {
                verdicts.push(Verdict::Inconclusive);
                let why = unreached(self.built, &stuck, &deaf);
                self.tell(Entry::LivenessNotEstablished { why });
            }
        }
        let built = self.built;
        for (k, model) in per_module.iter().enumerate() {
            let sub = dir.join(format!("module-{k}"));
            create_dir(&sub)?;
            let how = How {
                module: Some(&built.topology.modules[k].name),
                bounded_first: false,
            };
            let found = self.check_model(&sub, model, &checks, how)?;
            let violated = found.contains(&Verdict::Violated);
            verdicts.extend(found);
            if violated {
                self.tell(Entry::MaybeSpurious);
                break;
            }
        }
        Ok(verdicts)
    }

    /// Runs the checks on one model in `dir` (for safety on a large full model, bounded
    /// searches first; falling back to bitstate when the exhaustive search does not fit),
    /// an entry per check; explains the first violation and stops there.
    fn check_model(
        &mut self,
        dir: &Path,
        model: &Model,
        checks: &[Check],
        how: How,
    ) -> Result<Vec<Verdict>, VerifyError> {
        let path = dir.join("model.pml");
        std::fs::write(&path, &model.text)
            .map_err(|e| VerifyError::Internal(format!("cannot write {}: {e}", path.display())))?;
        let limits = self.limits();
        let mut verdicts = Vec::new();
        for &check in checks {
            let name = CheckName {
                module: how.module.map(str::to_string),
                check,
            };
            let bounded = if how.bounded_first && check == Check::Safety && !limits.bitstate {
                self.bounded_search(dir, &name, limits, model)?
            } else {
                None
            };
            let (result, used, fell_back) = match bounded {
                Some((result, used)) => (result, used, false),
                None => self.exhaustive(dir, &name, limits, model)?,
            };
            let verdict = if result.errors > 0 {
                Verdict::Violated
            } else if result.complete() {
                Verdict::Verified
            } else {
                Verdict::Inconclusive
            };
            self.tell(Entry::Checked {
                name,
                verdict,
                fell_back,
                result,
            });
            verdicts.push(verdict);
            if verdict == Verdict::Violated {
                let module = how.module.and_then(|m| built_module(self.built, m));
                let cx = self.counterexample(dir, check, used, model, module)?;
                self.tell(Entry::Counterexample(Box::new(cx)));
                break;
            }
        }
        Ok(verdicts)
    }

    /// The exhaustive search, then bitstate if it does not fit; the result, the limits it
    /// ran with, and whether it fell back.
    fn exhaustive(
        &mut self,
        dir: &Path,
        name: &CheckName,
        limits: Limits,
        model: &Model,
    ) -> Result<(PanResult, Limits, bool), VerifyError> {
        let label = name.to_string();
        let check = name.check;
        let result = self.search_anew(dir, check, limits, model, &label)?;
        if result.errors == 0 && !limits.bitstate && (result.out_of_memory || result.timed_out) {
            self.tell(Entry::FallingBack {
                name: name.clone(),
                result,
            });
            let bitstate = Limits {
                bitstate: true,
                ..limits
            };
            let result = self.search_anew(dir, check, bitstate, model, &label)?;
            return Ok((result, bitstate, true));
        }
        Ok((result, limits, false))
    }

    /// Builds the verifier for `limits` and searches, with progress under `label`.
    fn search_anew(
        &mut self,
        dir: &Path,
        check: Check,
        limits: Limits,
        model: &Model,
        label: &str,
    ) -> Result<PanResult, VerifyError> {
        let mut progress = Progress::new(label, &mut *self.observer);
        spin::run_model(dir, check, limits, model.processes, &mut progress)
    }

    /// Bounded searches (every run of at most [`BOUNDED_STEPS`] steps after `init`, the
    /// smallest first): `Some` when one found a violation or covered every state (no run
    /// reached the bound), with the limits it ran with; `None` to go on with the exhaustive
    /// search. A violation found is a real run, so stopping at the bound loses nothing but
    /// completeness.
    fn bounded_search(
        &mut self,
        dir: &Path,
        name: &CheckName,
        limits: Limits,
        model: &Model,
    ) -> Result<Option<(PanResult, Limits)>, VerifyError> {
        let label = name.to_string();
        let first = Limits {
            depth: Some(0),
            ..limits
        };
        let processes = model.processes;
        spin::build(
            dir,
            name.check,
            first,
            processes,
            &mut Progress::new(&label, &mut *self.observer),
        )?;
        for steps in BOUNDED_STEPS {
            let bounded = Limits {
                depth: Some(model.init_steps as u64 + steps),
                time_s: (limits.time_s / 4).max(1),
                ..limits
            };
            // A fresh progress per search: it has ended before the entry below is told.
            let result = spin::search(
                dir,
                name.check,
                bounded,
                &mut Progress::new(&label, &mut *self.observer),
            )?;
            self.tell(Entry::Bounded {
                name: name.clone(),
                steps,
                result: result.clone(),
            });
            if result.errors > 0 || result.complete() {
                return Ok(Some((result, bounded)));
            }
            if result.timed_out || result.out_of_memory {
                break;
            }
        }
        Ok(None)
    }

    /// Replays the trail of a violation (shortened first, for safety) and explains it in
    /// the source's terms.
    fn counterexample(
        &mut self,
        dir: &Path,
        check: Check,
        limits: Limits,
        model: &Model,
        module: Option<usize>,
    ) -> Result<Counterexample, VerifyError> {
        if check == Check::Safety && !limits.bitstate {
            self.shorten(dir, limits, model)?;
        }
        let output = spin::replay_trail(dir, check)?;
        let events = parse_events(&output);
        // pan reported an assertion violated; a replay that does not reach it is not a
        // counterexample to tell, and not a verdict either.
        if check == Check::Safety && !events.iter().any(|e| matches!(e, Event::Violation { .. })) {
            return Err(spin::tool_failure(spin::Tool::Replay, &output));
        }
        let cx = Context {
            ir: &self.built.ir,
            module_names: &model.module_names,
            paper_states: &model.paper_states,
            path: self.source.path,
            source: self.source.text,
        };
        let explanation = tell(&events, &cx);
        let copies = events
            .iter()
            .enumerate()
            .filter_map(|(k, e)| match e {
                Event::Copy { fields, .. } => Some((k, cx.copy(fields))),
                _ => None,
            })
            .collect();
        Ok(Counterexample {
            check,
            module,
            copies,
            text: explanation.to_string(),
            explanation,
            module_names: model.module_names.clone(),
            events,
        })
    }

    /// The first depth-first trail is rarely the shortest: searches again, shortening it
    /// iteratively (keeping the first trail if that runs out of memory).
    fn shorten(&mut self, dir: &Path, limits: Limits, model: &Model) -> Result<(), VerifyError> {
        let trail = dir.join("model.pml.trail");
        let kept = dir.join("dfs.trail");
        let _ = std::fs::rename(&trail, &kept);
        let bfs = Limits {
            shortest: true,
            ..limits
        };
        let again = self.search_anew(
            dir,
            Check::Safety,
            bfs,
            model,
            "shortening the counterexample",
        )?;
        if again.errors == 0 || !trail.exists() {
            let _ = std::fs::rename(&kept, &trail);
        }
        Ok(())
    }
}

/// The index of the module named `name` in the topology.
fn built_module(built: &Built, name: &str) -> Option<usize> {
    built.topology.modules.iter().position(|m| m.name == name)
}

fn create_dir(dir: &Path) -> Result<(), VerifyError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| VerifyError::Internal(format!("cannot create {}: {e}", dir.display())))
}

/// Why L cannot be established from the links that surely exist.
fn unreached(built: &Built, stuck: &[usize], deaf: &[usize]) -> String {
    let mut parts = Vec::new();
    for &s in stuck {
        parts.push(format!(
            "in stage {s}, what #{s} `{}` waits for cannot be shown to reach its module",
            built.ir.statements[s].text
        ));
    }
    if !deaf.is_empty() {
        let names: Vec<&str> = deaf
            .iter()
            .map(|&m| built.topology.modules[m].name.as_str())
            .collect();
        parts.push(format!(
            "in the final configuration, {} cannot be shown to hear every module that ran statements",
            names.join(", ")
        ));
    }
    parts.join("; ")
}
