//! The Promela back-end: a model of the compiled distributed state machine on a robot's
//! communication graph, for the spin model checker (`dynarole verify`).
//!
//! One process per module runs the same logic as the generated C (each `dr_module_step` and
//! each `dr_module_receive` is one indivisible step, as on a module); the statement tables come
//! from the same `lower::Ir` as the C, and the protocol logic is a line-by-line transcription of
//! the runtime, kept beside the C as templates (`runtime/lattice/dr_lattice.pml`,
//! `runtime/paper/dr_paper.pml`: every inline names the C function it mirrors), which
//! `promela/lattice.rs` and `promela/paper.rs` fill. Around it, the environment (the template
//! `runtime/dr_hal.pml`, filled here): links that deliver the sender's current copy at any
//! time or never, a bounded number of stale packets delivered late (and again), actuators that
//! finish after an unknown time, and a bounded number of module resets at any moment.
//!
//! Ghost variables record what happened physically (started and done operations, per epoch)
//! and the checks of the simulator (`dynarole-sim`, `ops.rs`) are assertions: S1 at every first
//! start, S2 at every re-issue, S3 when a module first declares the end. L is the LTL formula
//! `finishes` (`<>[]` every module knows the end), checked with weak fairness. The model prints
//! one `@` event line per step that matters (the vocabulary of `promela/events.rs`), which
//! `dynarole verify` reads back from spin's replay of a counterexample.
//!
//! **API boundary**: the caller passes the communication graph ([`Topology`]); this crate
//! knows nothing of geometry.

#[path = "promela/compositional.rs"]
mod compositional;
#[path = "promela/events.rs"]
pub mod events;
#[path = "promela/lattice.rs"]
mod lattice;
#[path = "promela/paper.rs"]
mod paper;
#[path = "promela/template.rs"]
mod template;
#[cfg(test)]
#[path = "promela/test_support.rs"]
mod test_support;

pub use compositional::{liveness_graph, LivenessGraph};

use crate::options::CompileOptions;
use crate::paper::pending_slots;
use crate::protocol::Protocol;
use dynarole_core::lower::{Ir, LimitError, PAPER_STATE_END};
use dynarole_core::span::Span;
use events::{expr, printf, value, Arg, EventKind};
use std::fmt::Write;
use template::{Holes, TemplateFile};

/// The environment of the models: `runtime/dr_hal.pml`.
static HAL: TemplateFile = TemplateFile {
    path: "runtime/dr_hal.pml",
    text: include_str!("../../../runtime/dr_hal.pml"),
};

/// Largest lattice window the model encodes (the done bits are one Promela `int`).
pub const MAX_MODEL_WINDOW: usize = 24;
/// Most modules a model may have (channels of the no-NV rule are bits of one `int`).
pub const MAX_MODEL_MODULES: usize = 30;

/// One module of the robot, as the model needs it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TopologyModule {
    /// The module's name in the configuration (for reports).
    pub name: String,
    /// The address its role predicates give it (`None`: it only relays).
    pub address: Option<u8>,
}

/// A directed link: `to` can hear `from`. It may deliver at any time (safety is checked
/// with every link of every configuration the reconfiguration goes through).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TopologyLink {
    pub from: usize,
    pub to: usize,
    /// Stages in which the link is assumed to deliver eventually (weak fairness, for L):
    /// stage k = statements 0..k are physically done and k is not (the first statements in
    /// source order; the caller decides in which stages the link surely exists).
    pub fair_stages: Vec<usize>,
}

/// Who can hear whom: computed by the caller from a configuration (and the replay).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topology {
    pub modules: Vec<TopologyModule>,
    pub links: Vec<TopologyLink>,
}

/// A deliberately broken protocol, to show that the checks can fail (tests only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Lattice join: the other copy's done bit of the lowest incomplete statement is dropped.
    JoinDropsDone,
    /// Lattice join: the low-water mark is raised without re-basing this copy's bits.
    JoinNoRebase,
}

/// What to model besides the protocol options.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ModelOptions {
    pub compile: CompileOptions,
    /// Module resets, at most, in the whole run (any module, any moment).
    pub resets: u8,
    /// The modules that may reset (indices into `Topology::modules`); empty: every module.
    pub reset_modules: Vec<usize>,
    /// Packets that can be held in flight and delivered late.
    pub late: u8,
    pub fault: Option<Fault>,
}

/// The generated model and what its events mean.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Model {
    pub text: String,
    /// For each Promela module index, the module's name.
    pub module_names: Vec<String>,
    /// Paper protocol: (first state, statements) of each unit of the layout; empty otherwise.
    pub paper_states: Vec<(u8, Vec<usize>)>,
    /// The steps `init` takes before the robot's first step (filling the tables, starting the
    /// processes): the depth at which a search meets the robot's initial state.
    pub init_steps: usize,
    /// The processes `init` starts (those of the liveness check included): the verifier's
    /// fairness bound depends on it.
    pub processes: usize,
}

/// The lines of `init` in a model's text that start with `word`.
fn init_lines(text: &str, word: &str) -> usize {
    text.split_once("\ninit {\n").map_or(0, |(_, init)| {
        init.lines()
            .filter(|l| l.trim_start().starts_with(word))
            .count()
    })
}

/// Counts `init`'s steps in a model's text: each `d_step` and each `run` is one step of the
/// search (those in `atomic` too).
fn init_steps(text: &str) -> usize {
    init_lines(text, "d_step") + init_processes(text)
}

/// Counts the processes `init` starts in a model's text: one per `run`.
fn init_processes(text: &str) -> usize {
    init_lines(text, "run ")
}

/// The limits every model shares.
fn validate(ir: &Ir, topology: &Topology, options: &ModelOptions) -> Result<(), LimitError> {
    let span = ir.statements.first().map_or(Span::default(), |s| s.span);
    let limit = |message: String| LimitError { message, span };
    options.compile.protocol.model().map_err(limit)?;
    if ir.statements.is_empty() {
        return Err(limit("the model needs at least one statement".into()));
    }
    if let Some(member) = ir.statements.iter().find(|s| s.synchronous.is_some()) {
        // Said rather than modelled without it: a proof of the model would not be a proof
        // of the runtime's start barrier (its liveness above all).
        return Err(LimitError {
            message: "the model of the lattice protocol does not include synchronous groups' start (the ready bits and the countdown); check the sequence with `check --from` and `simulate`".into(),
            span: member.span,
        });
    }
    if topology.modules.is_empty() || topology.modules.len() > MAX_MODEL_MODULES {
        return Err(limit(format!(
            "the model handles 1 to {MAX_MODEL_MODULES} modules; the configuration has {}",
            topology.modules.len()
        )));
    }
    if ir.statements.len() > 250 {
        return Err(limit("the model handles at most 250 statements".into()));
    }
    let window_encoded = match options.compile.protocol {
        Protocol::Lattice => true,
        Protocol::Paper | Protocol::Token => false,
    };
    if window_encoded && ir.window > MAX_MODEL_WINDOW {
        return Err(limit(format!(
            "the model encodes lattice windows up to {MAX_MODEL_WINDOW} statements; this sequence needs {}",
            ir.window
        )));
    }
    if options.compile.runs() == 0 {
        return Err(limit(
            "a model needs a finite number of epochs (runs of the sequence)".into(),
        ));
    }
    for a in ir.statements.iter().map(|s| s.address) {
        if !topology.modules.iter().any(|m| m.address == Some(a)) {
            return Err(limit(format!(
                "no module of the configuration has address {a}"
            )));
        }
    }
    Ok(())
}

/// Writes the Promela model of `ir` on `topology`.
pub fn generate_promela(
    ir: &Ir,
    topology: &Topology,
    options: &ModelOptions,
) -> Result<Model, LimitError> {
    validate(ir, topology, options)?;
    let span = ir.statements.first().map_or(Span::default(), |s| s.span);
    let limit = |message: String| LimitError { message, span };
    let g = Gen {
        ir,
        topology,
        options,
        checked: None,
    };
    let mut out = String::new();
    g.header(&mut out);
    let (paper_states, fill) = match options.compile.protocol {
        Protocol::Lattice => {
            lattice::write(&g, &mut out);
            (Vec::new(), String::new())
        }
        Protocol::Paper => {
            let written = paper::write(&g, &mut out, pending_slots(ir)?)?;
            (written.states, written.fill)
        }
        // Refused by `validate` with the table's message; said again rather than assumed.
        unmodelled @ Protocol::Token => {
            return Err(limit(unmodelled.model().err().unwrap_or_default()))
        }
    };
    g.processes(&mut out, &fill);
    Ok(Model {
        init_steps: init_steps(&out),
        processes: init_processes(&out),
        text: out,
        module_names: topology.modules.iter().map(|m| m.name.clone()).collect(),
        paper_states,
    })
}

/// Writes the compositional model of `ir` in which module `checked` (an index into
/// `topology.modules`) runs the lattice protocol's logic and every other module is abstract
/// (see `promela/compositional.rs`). `graph` says where the links carry what L needs.
pub fn generate_compositional(
    ir: &Ir,
    topology: &Topology,
    options: &ModelOptions,
    checked: usize,
    graph: &LivenessGraph,
) -> Result<Model, LimitError> {
    validate(ir, topology, options)?;
    let span = ir.statements.first().map_or(Span::default(), |s| s.span);
    let limit = |message: String| LimitError { message, span };
    let o = &options.compile;
    if !o.protocol.has_compositional_model() || o.without_nv() {
        return Err(limit(format!(
            "the compositional model is for the {} protocol with NV storage",
            Protocol::with_compositional_model()
        )));
    }
    if o.runs() != 1 {
        return Err(limit(
            "the compositional model checks one run of the sequence (--epochs 1)".into(),
        ));
    }
    if options.late > 0 {
        return Err(limit(
            "the compositional model has no late-packet slots (every packet may be any earlier state)".into(),
        ));
    }
    let mut addresses: Vec<u8> = topology.modules.iter().filter_map(|m| m.address).collect();
    addresses.sort_unstable();
    if addresses.windows(2).any(|w| w[0] == w[1]) {
        return Err(limit(
            "the compositional model needs one module per address".into(),
        ));
    }
    if checked >= topology.modules.len() {
        return Err(limit(format!("no module {checked} in the configuration")));
    }
    let g = Gen {
        ir,
        topology,
        options,
        checked: Some(checked),
    };
    let mut out = String::new();
    g.header(&mut out);
    compositional::write(&g, &mut out, checked, graph);
    Ok(Model {
        init_steps: init_steps(&out),
        processes: init_processes(&out),
        text: out,
        module_names: topology.modules.iter().map(|m| m.name.clone()).collect(),
        paper_states: Vec::new(),
    })
}

/// Shared by both protocols' writers.
pub(crate) struct Gen<'a> {
    pub ir: &'a Ir,
    pub topology: &'a Topology,
    pub options: &'a ModelOptions,
    /// The compositional model: the module whose logic is checked (the others are abstract).
    pub checked: Option<usize>,
}

impl Gen<'_> {
    pub fn n(&self) -> usize {
        self.ir.statements.len()
    }

    pub fn m(&self) -> usize {
        self.topology.modules.len()
    }

    pub fn epochs(&self) -> usize {
        usize::from(self.options.compile.runs().max(1))
    }

    /// Statements run by module `m`.
    pub fn statements_of(&self, m: usize) -> Vec<usize> {
        let Some(address) = self.topology.modules[m].address else {
            return Vec::new();
        };
        (0..self.n())
            .filter(|&s| self.ir.statements[s].address == address)
            .collect()
    }

    /// A conditional expression over modules: `(m == 0 -> a0 : (m == 1 -> a1 : a2))`.
    pub fn per_module(&self, var: &str, value: impl Fn(usize) -> String) -> String {
        let m = self.m();
        let mut expr = value(m - 1);
        for k in (0..m - 1).rev() {
            expr = format!("({var} == {k} -> {} : {expr})", value(k));
        }
        expr
    }

    /// The protocol's name and options, for the banner.
    fn protocol_title(&self) -> String {
        let o = &self.options.compile;
        o.describe()
    }

    /// The banner, the constants, the statement tables, the ghost state and the S1-S3 checks
    /// (`runtime/dr_hal.pml`, parts `banner` and `head`).
    fn header(&self, out: &mut String) {
        let statements: Vec<String> = (self.ir.statements.iter().enumerate())
            .map(|(i, s)| format!(" *   {i:>3}  {:>3}  {}", s.address, s.text))
            .collect();
        let modules: Vec<String> = (self.topology.modules.iter().enumerate())
            .map(|(k, m)| {
                let address = m.address.map_or("-".to_string(), |a| a.to_string());
                format!(" *   {k:>3}  {}  {address}", m.name)
            })
            .collect();
        let links: Vec<String> = (self.topology.links.iter())
            .map(|l| {
                let stages = stage_condition(&l.fair_stages);
                format!(" *   {} -> {}  {stages}", l.from, l.to)
            })
            .collect();
        out.push_str(
            &HAL.part("banner").fill(
                &Holes::new()
                    .text("name", &self.options.compile.name)
                    .text("robot", &self.ir.robot)
                    .text("protocol", self.protocol_title())
                    .text("statements", statements.join("\n"))
                    .text("modules", modules.join("\n"))
                    .text("links", links.join("\n")),
            ),
        );
        let addr = self.per_module("m", |k| {
            self.topology.modules[k]
                .address
                .map_or("NO_ADDRESS".to_string(), |a| a.to_string())
        });
        // A number: FINISHED is used before the paper model defines its STATE_END.
        let finished = match self.options.compile.protocol {
            Protocol::Lattice => "(epoch[m] >= N_EPOCHS)".to_string(),
            Protocol::Paper | Protocol::Token => format!("(g_state[m] == {PAPER_STATE_END})"),
        };
        let [deps, dependents, waits] = self.table_lists().map(|(_, _, lists)| {
            let total: usize = lists.iter().map(Vec::len).sum();
            total.max(1)
        });
        let all_done: Vec<String> = (0..self.epochs() * self.n())
            .map(|k| format!("g_done[{k}]"))
            .collect();
        let none_running: Vec<String> = (0..self.n()).map(|s| format!("!p_run[{s}]")).collect();
        let holes = Holes::new()
            .text("n", self.n())
            .text("m", self.m())
            .text("epochs", self.epochs())
            .flag("epochs", self.epochs() > 1)
            .text("resets", self.options.resets)
            .text("late", self.options.late)
            .text("addr", addr)
            .text("deps_size", deps)
            .text("dependents_size", dependents)
            .text("waits_size", waits)
            .text("finished", finished)
            .text("all_done", all_done.join(" && "))
            .text("none_running", none_running.join(" && "))
            .text("busy", self.busy())
            .text("interrupts", self.interrupts());
        out.push_str(&HAL.part("head").fill(&self.checks(holes)));
    }

    /// The `printf`s of the environment's events (issue, end, S1-S3).
    fn checks<'h>(&self, holes: Holes<'h>) -> Holes<'h> {
        let (m, s, e) = (expr("m"), expr("s"), expr("e"));
        let violation = |p: &str, s: Arg| printf(EventKind::Violation, &[value(p), m.clone(), s]);
        holes
            .text(
                "print_issue",
                printf(EventKind::Issue, &[m.clone(), s.clone(), e]),
            )
            .text("print_s1", violation("S1", s.clone()))
            .text("print_s2", violation("S2", s))
            .text(
                "print_end",
                printf(EventKind::End, std::slice::from_ref(&m)),
            )
            .text("print_s3", violation("S3", value(0)))
    }

    /// `BUSY(m)`: the HAL's dr_hal_op_status (ops.rs op_status: running while any operation
    /// the module started runs).
    fn busy(&self) -> String {
        self.per_module("m", |k| {
            let mine: Vec<String> = (self.statements_of(k).iter())
                .map(|s| format!("p_run[{s}]"))
                .collect();
            if mine.is_empty() {
                "0".into()
            } else {
                format!("({})", mine.join(" || "))
            }
        })
    }

    /// `interrupt(m)`'s branches: module m's operations stop.
    fn interrupts(&self) -> String {
        let branches: Vec<String> = (0..self.m())
            .filter_map(|k| {
                let mine: Vec<String> = (self.statements_of(k).iter())
                    .map(|s| format!("p_run[{s}] = 0"))
                    .collect();
                (!mine.is_empty()).then(|| format!("    :: m == {k} -> {}", mine.join("; ")))
            })
            .collect();
        branches.join("\n")
    }

    /// The statement lists the tables hold: (name, what, one list per statement).
    fn table_lists(&self) -> [(&'static str, &'static str, Vec<Vec<usize>>); 3] {
        let of = |f: &dyn Fn(&dynarole_core::lower::IrStatement) -> Vec<u16>| -> Vec<Vec<usize>> {
            self.ir
                .statements
                .iter()
                .map(|st| f(st).into_iter().map(usize::from).collect())
                .collect()
        };
        [
            (
                "deps",
                "the IR's dependencies (IrStatement::deps)",
                of(&|st| st.deps.clone()),
            ),
            (
                "dependents",
                "the statements that depend on it, transitively",
                self.ir.dependents(),
            ),
            (
                "waits",
                "what it waits for (dr_program_deps: its deps, the order the sequence means)",
                of(&|st| st.waits_for()),
            ),
        ]
    }

    /// `init`'s first steps: the tables filled (and the protocol's own, `extra`), in `d_step`s
    /// of at most 100 assignments (spin limits the length of a `d_step` and of an inline).
    pub fn table_steps(&self, extra: &str) -> String {
        let fill = self.table_fill() + extra;
        let lines: Vec<&str> = fill.lines().collect();
        lines
            .chunks(100)
            .map(|chunk| format!("    d_step {{\n{}\n    }};\n", chunk.join("\n")))
            .collect()
    }

    /// The assignments that fill the tables.
    fn table_fill(&self) -> String {
        let mut fill = String::new();
        for (k, st) in self.ir.statements.iter().enumerate() {
            let _ = writeln!(fill, "        st_addr[{k}] = {};", st.address);
        }
        for (name, _, lists) in &self.table_lists() {
            let mut at = 0;
            for (k, list) in lists.iter().enumerate() {
                let _ = writeln!(fill, "        {name}_first[{k}] = {at};");
                for d in list {
                    let _ = writeln!(fill, "        {name}_list[{at}] = {d};");
                    at += 1;
                }
            }
            let _ = writeln!(fill, "        {name}_first[{}] = {at};", self.n());
        }
        fill
    }

    /// Module, link, actuator, late-packet and reset processes, the LTL property, and `init`
    /// (`runtime/dr_hal.pml`, from part `processes` on).
    fn processes(&self, out: &mut String, fill: &str) {
        out.push_str(&HAL.part("processes").fill(&Holes::new()));
        for k in 0..self.m() {
            let holes = Holes::new()
                .text("k", k)
                .text("name", &self.topology.modules[k].name);
            out.push_str(&HAL.part("module").fill(&holes));
        }
        let deliveries: Vec<String> = (self.topology.links.iter())
            .map(|l| format!("    :: d_step {{ deliver({}, {}) }}", l.from, l.to))
            .collect();
        let holes = Holes::new().text("deliveries", deliveries.join("\n"));
        out.push_str(&HAL.part("radio").fill(&holes));
        let adaptive =
            self.options.compile.chosen_dissemination() == Some(crate::Dissemination::Adaptive);
        for l in &self.topology.links {
            let mut up = stage_condition(&l.fair_stages);
            if adaptive {
                // Adaptive dissemination: only deliveries that carry something are owed.
                let _ = write!(up, " && WANTS({}, {})", l.from, l.to);
            }
            let holes = Holes::new()
                .text("from", l.from)
                .text("to", l.to)
                .text("up", up);
            out.push_str(&HAL.part("link").fill(&holes));
        }
        self.actuators(out, |_| true);
        if self.options.resets > 0 {
            let branches: Vec<String> = (0..self.m())
                .filter(|k| {
                    self.options.reset_modules.is_empty() || self.options.reset_modules.contains(k)
                })
                .map(|k| {
                    let reset = printf(EventKind::Reset, &[value(k)]);
                    let guard = self.reset_guard();
                    format!("    :: left > 0 {guard} -> d_step {{ left--; {reset}; reset({k}) }}")
                })
                .collect();
            let holes = Holes::new().text("resets", branches.join("\n"));
            out.push_str(&HAL.part("resets").fill(&holes));
        }
        if self.options.late > 0 {
            self.late_process(out);
        }
        let finished: Vec<String> = (0..self.m()).map(|k| format!("FINISHED({k})")).collect();
        let holes = Holes::new().text("finished", finished.join(" && "));
        out.push_str(&HAL.part("ltl").fill(&holes));
        let mut runs: Vec<String> = (0..self.m())
            .map(|k| format!("        run module_{k}();"))
            .collect();
        runs.extend(
            (self.topology.links.iter())
                .map(|l| format!("        run link_{}_{}();", l.from, l.to)),
        );
        runs.extend(
            (0..self.m())
                .filter(|&k| !self.statements_of(k).is_empty())
                .map(|k| format!("        run actuator_{k}();")),
        );
        let holes = Holes::new()
            .text("tables", self.table_steps(fill))
            .text("runs", runs.join("\n"))
            .flag("resets", self.options.resets > 0)
            .flag("late", self.options.late > 0);
        out.push_str(&HAL.part("init").fill(&holes));
    }

    /// One process per module with statements (the modules in `which`): a started operation
    /// finishes after an unknown time.
    pub fn actuators(&self, out: &mut String, which: impl Fn(usize) -> bool) {
        for k in (0..self.m()).filter(|&k| which(k)) {
            let mine = self.statements_of(k);
            if mine.is_empty() {
                continue;
            }
            let finishes: Vec<String> = mine.iter().map(|&s| self.finish_branch(k, s)).collect();
            let holes = Holes::new()
                .text("k", k)
                .text("finishes", finishes.concat().trim_end());
            out.push_str(&HAL.part("actuator").fill(&holes));
        }
    }

    /// The `do` branch in which module k's operation of statement s finishes (physically),
    /// with its newline.
    pub fn finish_branch(&self, k: usize, s: usize) -> String {
        let epoch = if self.epochs() > 1 {
            format!("p_epoch[{s}]")
        } else {
            "0".into()
        };
        let holes = Holes::new()
            .text("s", s)
            .text("epoch", epoch)
            .text("print_done", printf(EventKind::Done, &[value(k), value(s)]));
        HAL.part("finish").fill(&holes)
    }

    /// With the lattice's no-NV rules, assumption (a) of runtime/lattice/README.md: a module
    /// resets only when every module that reset before has heard all its neighbours.
    fn reset_guard(&self) -> String {
        if self.options.compile.without_nv() {
            let quiet: Vec<String> = (0..self.m())
                .map(|m| format!("unheard[{m}] == 0"))
                .collect();
            format!("&& {}", quiet.join(" && "))
        } else {
            String::new()
        }
    }

    /// Stale packets: LATE slots, each holding a copy of a sender's state taken at some
    /// moment, delivered later (any number of times in the safety check; once, and at most
    /// LATE packets in all, in the liveness check, so that a replayed packet cannot be the
    /// reason a run never ends).
    fn late_process(&self, out: &mut String) {
        let mut slots = String::new();
        for slot in 0..usize::from(self.options.late) {
            for l in &self.topology.links {
                let capture = [value(slot), value(l.from), value(l.to)];
                let holes = Holes::new()
                    .text("slot", slot)
                    .text("from", l.from)
                    .text("to", l.to)
                    .text("print_capture", printf(EventKind::Capture, &capture));
                slots.push_str(&HAL.part("late_capture").fill(&holes));
            }
            let from_to = [
                value(slot),
                expr(format!("l_from[{slot}]")),
                expr(format!("l_to[{slot}]")),
            ];
            let holes = Holes::new()
                .text("slot", slot)
                .text("print_late", printf(EventKind::Late, &from_to));
            slots.push_str(&HAL.part("late_slot").fill(&holes));
        }
        let holes = Holes::new().text("slots", slots.trim_end());
        out.push_str(&HAL.part("late").fill(&holes));
    }
}

/// `(stage >= 0 && stage <= 3 || stage == 7)` for the stages given; `false` for none.
fn stage_condition(stages: &[usize]) -> String {
    let mut sorted: Vec<usize> = stages.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut ranges: Vec<(usize, usize)> = Vec::new();
    for s in sorted {
        match ranges.last_mut() {
            Some((_, hi)) if *hi + 1 == s => *hi = s,
            _ => ranges.push((s, s)),
        }
    }
    if ranges.is_empty() {
        return "false".into();
    }
    let parts: Vec<String> = ranges
        .iter()
        .map(|&(lo, hi)| {
            if lo == hi {
                format!("stage == {lo}")
            } else {
                format!("(stage >= {lo} && stage <= {hi})")
            }
        })
        .collect();
    format!("({})", parts.join(" || "))
}

#[cfg(test)]
#[path = "../tests/unit/promela.rs"]
mod tests;
