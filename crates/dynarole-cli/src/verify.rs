//! `dynarole verify`: model-checks a compiled sequence on a configuration with spin (S1, S2,
//! S3 and L under stated bounds) and reports a counterexample in the source's terms; also
//! the model itself for `dynarole compile --target promela`.

use crate::compile::{ProtocolArg, ProtocolOptions};
use crate::counterexample::{explain, parse_events, Context, Event};
use crate::load::{self, Failure, PluginArgs};
use crate::render;
use crate::spin::{self, Check, Limits, PanResult};
use crate::world::{prepare, read_configuration};
use dynarole_codegen::{
    generate_compositional, generate_promela, liveness_graph, Fault, LivenessGraph, Model,
    ModelOptions, Protocol, Topology, TopologyLink, TopologyModule,
};
use dynarole_core::check::Label;
use dynarole_core::lower::Ir;
use dynarole_core::{Diagnostic, DiagnosticKind, Program};
use dynarole_replay::{communication_graph, CommGraph};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The bounds of the environment, shared by `verify` and `compile --target promela`.
#[derive(Clone, Debug, clap::Args)]
pub struct ModelArgs {
    /// Module resets, at most, in a run (any module, at any moment, mid-operation included).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub resets: u8,
    /// Only this module may reset (its name in the configuration); may be repeated.
    #[arg(long = "reset-only", value_name = "MODULE")]
    pub reset_only: Vec<String>,
    /// Packets that can be in flight at once and be delivered late (again and again, so also
    /// duplicated and reordered). Losses are not bounded: any packet may be lost.
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub late: u8,
    /// How to model the robot: `full` (every module's logic and every link), `compositional`
    /// (lattice only: one model per module, every packet any state the robot has reached;
    /// scales to large robots), `auto` (compositional for the lattice protocol on more than
    /// three modules).
    #[arg(long, value_enum, default_value_t = Method::Auto)]
    pub method: Method,
}

/// How the robot is modelled (see docs/verification.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    Auto,
    Full,
    Compositional,
}

/// Modules above which the full model's exhaustive search is not expected to finish: `auto`
/// then chooses the compositional model for the lattice protocol, and a full model is first
/// searched within bounds ([`BOUNDED_STEPS`]).
const AUTO_FULL_MODULES: usize = 3;

/// A deliberately broken lattice protocol (for the tests of the checker itself).
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum FaultArg {
    /// The join drops the other copy's done bit of the lowest incomplete statement.
    JoinDropsDone,
    /// The join raises the low-water mark without re-basing the bits.
    JoinNoRebase,
}

/// What `verify` was asked to do.
pub struct VerifyArgs<'a> {
    pub file: &'a Path,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
    pub memory_mb: u64,
    pub time_s: u64,
    pub bitstate: bool,
    pub safety_only: bool,
    pub keep: Option<&'a Path>,
    pub fault: Option<FaultArg>,
    pub record: &'a crate::view::RecordArgs,
    pub plugins: &'a PluginArgs,
}

/// A model and what it was made from.
pub struct Built {
    pub ir: Ir,
    pub models: Models,
    pub topology: Topology,
    pub graph: CommGraph,
    pub name: String,
    /// The statements as lowered (the model's statement numbers) and the start, for a
    /// counterexample's recording.
    pub statements: Vec<dynarole_core::check::ResolvedStatement>,
    pub start: dynarole_world::Configuration,
}

/// The full model, or one compositional model per module.
pub enum Models {
    Full(Model),
    Compositional {
        /// One per module of the topology, in its order.
        per_module: Vec<Model>,
        liveness: LivenessGraph,
    },
}

/// What a model is made from: a checked source, its sequences, a configuration, options.
pub struct Request<'a> {
    pub program: &'a Program<'a>,
    pub source: &'a str,
    pub display: &'a str,
    pub sequences: &'a [String],
    pub from: &'a Path,
    pub options: &'a ProtocolOptions,
    pub model: &'a ModelArgs,
    pub epochs: u16,
}

/// Expands, lowers and models the sequences on the configuration. `Err(code)` inside: the
/// problem was rendered as a diagnostic of the source.
pub fn build(req: &Request, fault: Option<FaultArg>) -> Result<Result<Built, ExitCode>, Failure> {
    let Request {
        program,
        source,
        display,
        sequences,
        from,
        options,
        model,
        epochs,
    } = *req;
    let config = read_configuration(from)?;
    let prepared = match prepare(program, display, sequences, config)? {
        Ok(p) => p,
        Err(diagnostics) => {
            render::diagnostics(display, source, &diagnostics);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    if let ProtocolArg::Paper = options.protocol {
        for plan in &prepared.plans {
            if let Err(d) = plan.flatten_for_paper() {
                render::diagnostics(display, source, &[d]);
                return Ok(Err(ExitCode::from(1)));
            }
        }
    }
    let limit_error = |e: dynarole_core::lower::LimitError| {
        Diagnostic::new(DiagnosticKind::TargetLimit { message: e.message }, e.span)
    };
    let ir = match program.lower(&prepared.plans) {
        Ok(ir) => ir,
        Err(e) => {
            render::diagnostics(display, source, &[limit_error(e)]);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    let graph = communication_graph(
        program,
        &prepared.plans,
        prepared.world.clone(),
        &prepared.assignment,
    );
    let topology = topology(&ir, &graph, &prepared.assignment)?;
    let name = prepared.names.join(" + ");
    let mut reset_modules = Vec::new();
    for wanted in &model.reset_only {
        match graph.names.iter().position(|n| n == wanted) {
            Some(k) => reset_modules.push(k),
            None => {
                return Err(Failure::Usage(format!(
                    "--reset-only {wanted}: no module of that name in {}",
                    from.display()
                )))
            }
        }
    }
    let model_options = ModelOptions {
        compile: options.compile_options(epochs, name.clone()),
        resets: model.resets,
        reset_modules,
        late: model.late,
        fault: fault.map(|f| match f {
            FaultArg::JoinDropsDone => Fault::JoinDropsDone,
            FaultArg::JoinNoRebase => Fault::JoinNoRebase,
        }),
    };
    if model_options.compile.protocol != Protocol::Lattice && fault.is_some() {
        return Err(Failure::Usage(
            "the broken variants exist for the lattice protocol only".into(),
        ));
    }
    let o = &model_options.compile;
    if model.method == Method::Compositional
        && (o.protocol != Protocol::Lattice || o.no_nv || o.epochs != 1)
    {
        return Err(Failure::Usage(
            "--method compositional models the lattice protocol with NV storage and one run (--epochs 1); use --method full".into(),
        ));
    }
    let models = match generate(&ir, &topology, &model_options, model.method) {
        Ok(m) => m,
        Err(e) => {
            render::diagnostics(display, source, &[limit_error(e)]);
            return Ok(Err(ExitCode::from(1)));
        }
    };
    let statements = prepared
        .plans
        .iter()
        .flat_map(|p| p.statements().into_iter().cloned())
        .collect();
    Ok(Ok(Built {
        ir,
        models,
        topology,
        graph,
        name,
        statements,
        start: prepared.world.configuration(),
    }))
}

/// Whether the compositional model is used: asked for, or `auto` on a lattice robot of more
/// than AUTO_FULL_MODULES modules (one run, NV, no broken variant).
fn compositional(options: &ModelOptions, modules: usize, method: Method) -> bool {
    let o = &options.compile;
    match method {
        Method::Full => false,
        Method::Compositional => true,
        Method::Auto => {
            o.protocol == Protocol::Lattice
                && !o.no_nv
                && o.epochs == 1
                && options.fault.is_none()
                && modules > AUTO_FULL_MODULES
        }
    }
}

fn generate(
    ir: &Ir,
    topology: &Topology,
    options: &ModelOptions,
    method: Method,
) -> Result<Models, dynarole_core::lower::LimitError> {
    if !compositional(options, topology.modules.len(), method) {
        return generate_promela(ir, topology, options).map(Models::Full);
    }
    // Late packets are subsumed: every packet is any state the robot has already reached.
    let options = ModelOptions {
        late: 0,
        ..options.clone()
    };
    let liveness = liveness_graph(ir, topology);
    let per_module = (0..topology.modules.len())
        .map(|k| generate_compositional(ir, topology, &options, k, &liveness))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Models::Compositional {
        per_module,
        liveness,
    })
}

/// The model's view of the robot: every module of the configuration with the address of the
/// label assigned to it, and its links (fair when they exist throughout).
fn topology(
    ir: &Ir,
    graph: &CommGraph,
    assignment: &dynarole_replay::Assignment,
) -> Result<Topology, Failure> {
    let mut modules = Vec::new();
    for name in &graph.names {
        let labels: Vec<&Label> = assignment
            .iter()
            .filter(|(_, module)| *module == name)
            .map(|(label, _)| label)
            .collect();
        let addresses: Vec<u8> = labels
            .iter()
            .filter_map(|l| ir.addresses.iter().find(|a| a.label == **l))
            .map(|a| a.number)
            .collect();
        if addresses.len() > 1 {
            return Err(Failure::Input(format!(
                "module {name} has several roles; the model needs one address per module"
            )));
        }
        modules.push(TopologyModule {
            name: name.clone(),
            address: addresses.first().copied(),
        });
    }
    // A link surely exists in stage k (statements 0..k done, k not) when it exists in every
    // configuration from the one after the first k statements to the one after the group
    // (up to the next `;`) that statement k belongs to; in the last stage, in the final one.
    let n = ir.statements.len();
    let group_end = |k: usize| -> usize {
        (k..n)
            .find(|&j| ir.statements[j].separator == dynarole_core::ast::SeparatorKind::Sequential)
            .map_or(n, |j| j + 1)
    };
    let all: std::collections::BTreeSet<(usize, usize)> =
        graph.always.union(&graph.sometimes).copied().collect();
    let links = all
        .into_iter()
        .map(|(from, to)| {
            let fair_stages = (0..=n)
                .filter(|&k| {
                    let last = if k == n { n } else { group_end(k) };
                    (k..=last).all(|t| graph.stages.get(t).is_some_and(|s| s.contains(&(from, to))))
                })
                .collect();
            TopologyLink {
                from,
                to,
                fair_stages,
            }
        })
        .collect();
    Ok(Topology { modules, links })
}

pub fn run(args: &VerifyArgs) -> Result<ExitCode, Failure> {
    if let ProtocolArg::Token = args.options.protocol {
        return Err(Failure::Usage(
            "verify models the lattice and paper protocols; the token baseline is not modelled"
                .into(),
        ));
    }
    load::with_program(args.file, args.plugins, |program, source| {
        let display = args.file.display().to_string();
        let request = Request {
            program,
            source,
            display: &display,
            sequences: args.sequences,
            from: args.from,
            options: args.options,
            model: args.model,
            epochs: args.epochs,
        };
        let built = match build(&request, args.fault)? {
            Ok(b) => b,
            Err(code) => return Ok(code),
        };
        spin::check_tools()?;
        let dir = match args.keep {
            Some(d) => d.to_path_buf(),
            None => scratch_dir(),
        };
        std::fs::create_dir_all(&dir)
            .map_err(|e| Failure::Internal(format!("cannot create {}: {e}", dir.display())))?;
        let result = verify_in(&dir, args, &built, &display, source, &program.robot);
        if args.keep.is_none() {
            let _ = std::fs::remove_dir_all(&dir);
        }
        result
    })
}

fn scratch_dir() -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    std::env::temp_dir().join(format!("dynarole-verify-{}-{nanos}", std::process::id()))
}

/// Whether a property was proved, refuted, or neither.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    Verified,
    Violated,
    Inconclusive,
}

fn verify_in(
    dir: &Path,
    args: &VerifyArgs,
    built: &Built,
    display: &str,
    source: &str,
    robot: &dynarole_core::robot::RobotApi,
) -> Result<ExitCode, Failure> {
    print_header(args, built);
    let explain_with = Explain {
        ir: &built.ir,
        display,
        source,
        record: args.record.wanted().then_some(Recorder {
            args: args.record,
            robot,
            built,
        }),
    };
    let verdicts = match &built.models {
        Models::Full(model) => {
            let checks = if args.safety_only {
                vec![Check::Safety]
            } else {
                vec![Check::Safety, Check::Liveness]
            };
            let bounded_first = built.topology.modules.len() > AUTO_FULL_MODULES;
            let how = How {
                who: "",
                bounded_first,
            };
            check_model(dir, args, model, &checks, how, &explain_with)?
        }
        Models::Compositional {
            per_module,
            liveness,
        } => check_each_module(dir, args, built, per_module, liveness, &explain_with)?,
    };
    let code = if verdicts.contains(&Verdict::Violated) {
        println!("result: violated");
        1
    } else if verdicts.iter().all(|v| *v == Verdict::Verified) {
        println!("result: verified");
        0
    } else {
        println!("result: inconclusive (the search did not cover every state; see above)");
        3
    };
    Ok(ExitCode::from(code))
}

/// What a counterexample is explained with.
struct Explain<'a> {
    ir: &'a Ir,
    display: &'a str,
    source: &'a str,
    /// Where a counterexample's recording goes, when one is asked for.
    record: Option<Recorder<'a>>,
}

/// What a counterexample's recording is made from.
struct Recorder<'a> {
    args: &'a crate::view::RecordArgs,
    robot: &'a dynarole_core::robot::RobotApi,
    built: &'a Built,
}

impl Recorder<'_> {
    /// The trail's steps on the robot, the broken property marked where it breaks.
    fn write(
        &self,
        events: &[Event],
        names: &[String],
        cx: &Explain,
        context: &Context,
        explained: &str,
    ) -> Result<(), Failure> {
        use crate::view::Step;
        let name = |m: &usize| names.get(*m).cloned().unwrap_or_default();
        let mut broken = Vec::new();
        let steps: Vec<Step> = events
            .iter()
            .filter_map(|e| match e {
                Event::Issue { m, s, .. } => Some(Step::Issue(*s, name(m))),
                Event::Done { m, s } => Some(Step::Done(*s, name(m))),
                Event::Reset { m } => Some(Step::Reset(name(m))),
                Event::Copy { m, fields } => Some(Step::Copy(name(m), context.copy(fields))),
                Event::Violation { property, m, s } => {
                    broken.push(property.clone());
                    let text = cx.ir.statements.get(*s).map_or("", |st| st.text.as_str());
                    Some(Step::Violation(
                        name(m),
                        format!("#{s} {text}: {property} broken here"),
                    ))
                }
                _ => None,
            })
            .collect();
        let title = format!("counterexample of {} ({})", self.built.name, cx.display);
        let mut notes = vec![format!("VIOLATED: {}", broken.join(", "))];
        notes.extend(explained.lines().map(str::to_string));
        let recording = crate::view::ModelRun {
            kind: "counterexample",
            title: &title,
            robot: self.robot,
            steps: &steps,
            statements: &self.built.statements,
            start: &self.built.start,
            source: Some(dynarole_recording::Source {
                name: cx.display,
                text: cx.source,
            }),
        }
        .record(notes)?;
        self.args.write(&recording)
    }
}

/// The compositional method: the modules one at a time (each model in its own directory),
/// stopping at the first violation; L only where the links that surely exist carry what it
/// needs.
fn check_each_module(
    dir: &Path,
    args: &VerifyArgs,
    built: &Built,
    per_module: &[Model],
    liveness: &LivenessGraph,
    explain_with: &Explain,
) -> Result<Vec<Verdict>, Failure> {
    println!("method: compositional, one model per module (its own logic; every other module reduced to its start rule; every packet any dependency-closed state the robot has reached: any loss, delay, duplication, reordering, on any topology)");
    let mut verdicts = Vec::new();
    let mut checks = vec![Check::Safety];
    if !args.safety_only {
        let stuck = liveness.stuck_statements();
        let deaf = liveness.deaf_modules();
        if stuck.is_empty() && deaf.is_empty() {
            println!("  links for L: in every stage, the dependencies of the next statement reach its module, and at the end every module is reached, over links that surely exist");
            checks.push(Check::Liveness);
        } else {
            verdicts.push(Verdict::Inconclusive);
            println!(
                "  L: not established (NOT checked): {}",
                unreached(built, &stuck, &deaf)
            );
        }
    }
    for (k, model) in per_module.iter().enumerate() {
        let name = &built.topology.modules[k].name;
        let sub = dir.join(format!("module-{k}"));
        std::fs::create_dir_all(&sub)
            .map_err(|e| Failure::Internal(format!("cannot create {}: {e}", sub.display())))?;
        let how = How {
            who: name,
            bounded_first: false,
        };
        let found = check_model(&sub, args, model, &checks, how, explain_with)?;
        let violated = found.contains(&Verdict::Violated);
        verdicts.extend(found);
        if violated {
            println!("note: the compositional model over-approximates the network, so a violation may be spurious; check it with --method full");
            break;
        }
    }
    Ok(verdicts)
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

/// How one model is checked.
#[derive(Clone, Copy)]
struct How<'a> {
    /// The module a compositional model is for (empty: the full model).
    who: &'a str,
    /// Look for a short violation first (bounded searches, [`BOUNDED_STEPS`]): the full model
    /// of a robot larger than [`AUTO_FULL_MODULES`] modules, whose exhaustive search runs deep
    /// before it backtracks to a violation a few steps from the start.
    bounded_first: bool,
}

/// The bounds of the searches tried first (steps after `init`), each run only when the last
/// met its bound without a violation; each gets a quarter of the time limit.
const BOUNDED_STEPS: [u64; 3] = [50, 100, 200];

/// Runs the checks on one model in `dir` (for safety on a large full model, bounded searches
/// first; falling back to bitstate when the exhaustive search does not fit), prints a line
/// per check, explains the first violation and stops there.
fn check_model(
    dir: &Path,
    args: &VerifyArgs,
    model: &Model,
    checks: &[Check],
    how: How,
    explain_with: &Explain,
) -> Result<Vec<Verdict>, Failure> {
    let path = dir.join("model.pml");
    std::fs::write(&path, &model.text)
        .map_err(|e| Failure::Internal(format!("cannot write {}: {e}", path.display())))?;
    let limits = Limits {
        memory_mb: args.memory_mb,
        time_s: args.time_s,
        bitstate: args.bitstate,
        shortest: false,
        depth: None,
    };
    let who = if how.who.is_empty() {
        String::new()
    } else {
        format!("{}: ", how.who)
    };
    let mut verdicts = Vec::new();
    for &check in checks {
        let label = match (check, who.is_empty()) {
            (Check::Safety, true) => "S1, S2, S3 (safety)",
            (Check::Safety, false) => "S1, S2, S3, G1-G4 (safety)",
            (Check::Liveness, _) => "L (finishes, weak fairness)",
        };
        let named = format!("{who}{label}");
        let bounded = if how.bounded_first && check == Check::Safety && !limits.bitstate {
            bounded_search(dir, check, limits, model, &named)?
        } else {
            None
        };
        let (result, used, fell_back) = match bounded {
            Some(found) => (found.0, found.1, false),
            None => exhaustive(dir, check, limits, &named)?,
        };
        let verdict = if result.errors > 0 {
            Verdict::Violated
        } else if result.complete() {
            Verdict::Verified
        } else {
            Verdict::Inconclusive
        };
        let word = match verdict {
            Verdict::Verified => "verified",
            Verdict::Violated => "VIOLATED",
            Verdict::Inconclusive => {
                if fell_back || result.bitstate {
                    "no violation found (NOT a proof)"
                } else {
                    "not finished (NOT a proof)"
                }
            }
        };
        println!("  {named}: {word} — {}", describe(&result));
        verdicts.push(verdict);
        if verdict == Verdict::Violated {
            explain_violation(dir, check, used, model, explain_with)?;
            break;
        }
    }
    Ok(verdicts)
}

/// The exhaustive search, then bitstate if it does not fit; the result, the limits it ran
/// with, and whether it fell back.
fn exhaustive(
    dir: &Path,
    check: Check,
    limits: Limits,
    named: &str,
) -> Result<(PanResult, Limits, bool), Failure> {
    let result = spin::run_check(dir, check, limits, named)?;
    if result.errors == 0 && !limits.bitstate && (result.out_of_memory || result.timed_out) {
        println!(
            "  {named}: the state space is too large for an exhaustive search ({}); trying a bitstate search",
            describe(&result)
        );
        let bitstate = Limits {
            bitstate: true,
            ..limits
        };
        return Ok((
            spin::run_check(dir, check, bitstate, named)?,
            bitstate,
            true,
        ));
    }
    Ok((result, limits, false))
}

/// Bounded searches (every run of at most [`BOUNDED_STEPS`] steps after `init`, the smallest
/// first): `Some` when one found a violation or covered every state (no run reached the
/// bound), with the limits it ran with; `None` to go on with the exhaustive search. A
/// violation found is a real run, so stopping at the bound loses nothing but completeness.
fn bounded_search(
    dir: &Path,
    check: Check,
    limits: Limits,
    model: &Model,
    named: &str,
) -> Result<Option<(PanResult, Limits)>, Failure> {
    let first = Limits {
        depth: Some(0),
        ..limits
    };
    spin::build(dir, check, first, &mut spin::Progress::new(named))?;
    for steps in BOUNDED_STEPS {
        let bounded = Limits {
            depth: Some(model.init_steps as u64 + steps),
            time_s: (limits.time_s / 4).max(1),
            ..limits
        };
        // A fresh progress per search: its spinner is gone before the line below is printed.
        let result = spin::search(dir, check, bounded, &mut spin::Progress::new(named))?;
        let outcome = if result.errors > 0 {
            "a violation"
        } else if result.complete() {
            "no violation, and no run reaches the bound"
        } else {
            "no violation within the bound"
        };
        println!(
            "  {named}: bounded search, runs of at most {steps} steps: {outcome} — {}",
            describe(&result)
        );
        if result.errors > 0 || result.complete() {
            return Ok(Some((result, bounded)));
        }
        if result.timed_out || result.out_of_memory {
            break;
        }
    }
    Ok(None)
}

/// Replays the trail of a violation (shortened first, for safety) and prints it in the
/// source's terms.
fn explain_violation(
    dir: &Path,
    check: Check,
    limits: Limits,
    model: &Model,
    explain_with: &Explain,
) -> Result<(), Failure> {
    if check == Check::Safety && !limits.bitstate {
        // The first depth-first trail is rarely the shortest: search again, shortening
        // it iteratively (keeping the first trail if that runs out of memory).
        let trail = dir.join("model.pml.trail");
        let kept = dir.join("dfs.trail");
        let _ = std::fs::rename(&trail, &kept);
        let bfs = Limits {
            shortest: true,
            ..limits
        };
        let again = spin::run_check(dir, check, bfs, "shortening the counterexample")?;
        if again.errors == 0 || !trail.exists() {
            let _ = std::fs::rename(&kept, &trail);
        }
    }
    let output = spin::replay_trail(dir, check)?;
    let events = parse_events(&output);
    // pan reported an assertion violated; a replay that does not reach it is not a
    // counterexample to tell, and not a verdict either.
    if check == Check::Safety && !events.iter().any(|e| matches!(e, Event::Violation { .. })) {
        return Err(spin::tool_failure(spin::Tool::Replay, &output));
    }
    let cx = Context {
        ir: explain_with.ir,
        module_names: &model.module_names,
        paper_states: &model.paper_states,
        path: explain_with.display,
        source: explain_with.source,
    };
    let explained = explain(&events, &cx);
    println!();
    print!("{explained}");
    if let Some(recorder) = &explain_with.record {
        recorder.write(&events, &model.module_names, explain_with, &cx, &explained)?;
    }
    Ok(())
}

/// `exhaustive, 1234 states, depth 56, 0.10 s` and what limited the search.
fn describe(r: &PanResult) -> String {
    let mut parts = vec![
        if r.bitstate {
            "bitstate (partial)".to_string()
        } else if r.depth_limited || (r.bounded && !r.complete()) {
            "bounded (partial)".to_string()
        } else {
            "exhaustive".to_string()
        },
        // pan reports its figures every million states and at the end: a search stopped
        // before either has none to give.
        if r.states == 0 && !r.reported {
            "states not reported".to_string()
        } else {
            format!("{} states, depth {}", r.states, r.depth)
        },
        format!("{:.2} s", r.seconds),
    ];
    if r.memory_mb > 0.0 {
        parts.push(format!("{:.0} MB", r.memory_mb));
    }
    if r.out_of_memory {
        parts.push("out of memory".into());
    }
    if r.timed_out {
        parts.push("time limit reached".into());
    }
    if r.depth_limited {
        parts.push("depth limit reached".into());
    }
    parts.join(", ")
}

fn print_header(args: &VerifyArgs, built: &Built) {
    let protocol = match args.options.protocol {
        ProtocolArg::Lattice => {
            if args.options.no_nv {
                "lattice protocol without NV".to_string()
            } else {
                "lattice protocol".to_string()
            }
        }
        ProtocolArg::Paper => format!(
            "paper protocol, {:?} merge{}{}",
            args.options.merge,
            if args.options.single_step_handover {
                ", single-step handover"
            } else {
                ""
            },
            if args.options.restart_pending {
                ", pending restart"
            } else {
                ""
            }
        )
        .replace("CPort", "c-port")
        .replace("Java", "java")
        .replace("Printed", "printed"),
        ProtocolArg::Token => "token baseline".to_string(),
    };
    let stages = built.ir.statements.len() + 1;
    let throughout = built
        .topology
        .links
        .iter()
        .filter(|l| l.fair_stages.len() == stages)
        .count();
    println!(
        "verify {} on {} ({protocol}): {} statements, {} modules, {} links ({} throughout, {} part of the time)",
        built.name,
        args.from.display(),
        built.ir.statements.len(),
        built.topology.modules.len(),
        built.topology.links.len(),
        throughout,
        built.topology.links.len() - throughout
    );
    let epochs = match args.options.protocol {
        ProtocolArg::Lattice => format!("{} run(s) of the sequence", args.epochs.max(1)),
        ProtocolArg::Paper | ProtocolArg::Token => "one run".to_string(),
    };
    let who = if args.model.reset_only.is_empty() {
        String::new()
    } else {
        format!(" (of {} only)", args.model.reset_only.join(", "))
    };
    let late = match built.models {
        Models::Full(_) => format!(
            "at most {} packet(s) in flight delivered late (and again)",
            args.model.late
        ),
        Models::Compositional { .. } => {
            "any number of packets delivered late (and again)".to_string()
        }
    };
    println!(
        "bounds: at most {} reset(s){who}; {late}; any packet may be lost; {epochs}; operations never fail",
        args.model.resets
    );
    if args.fault.is_some() {
        println!("note: a deliberately broken variant of the protocol is checked (--fault)");
    }
}

/// `dynarole compile --target promela`: writes DIR/model.pml (the compositional method:
/// DIR/model-MODULE.pml for each module).
pub fn write_model(req: &Request, out_dir: &Path) -> Result<ExitCode, Failure> {
    let built = match build(req, None)? {
        Ok(b) => b,
        Err(code) => return Ok(code),
    };
    std::fs::create_dir_all(out_dir)
        .map_err(|e| Failure::Input(format!("cannot create {}: {e}", out_dir.display())))?;
    let files: Vec<(PathBuf, &Model)> = match &built.models {
        Models::Full(model) => vec![(out_dir.join("model.pml"), model)],
        Models::Compositional { per_module, .. } => per_module
            .iter()
            .zip(&built.topology.modules)
            .map(|(model, m)| (out_dir.join(format!("model-{}.pml", m.name)), model))
            .collect(),
    };
    for (path, model) in &files {
        std::fs::write(path, &model.text)
            .map_err(|e| Failure::Input(format!("cannot write {}: {e}", path.display())))?;
    }
    let what = match built.models {
        Models::Full(_) => "model",
        Models::Compositional { .. } => "compositional models",
    };
    println!(
        "{what} of {}: {} statements, {} modules, {} links -> {}",
        built.name,
        built.ir.statements.len(),
        built.topology.modules.len(),
        built.topology.links.len(),
        files
            .iter()
            .map(|(p, _)| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(ExitCode::SUCCESS)
}
