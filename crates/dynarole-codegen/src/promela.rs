//! The Promela back-end: a model of the compiled distributed state machine on a robot's
//! communication graph, for the spin model checker (`dynarole verify`).
//!
//! One process per module runs the same logic as the generated C (each `dr_module_step` and
//! each `dr_module_receive` is one indivisible step, as on a module); the statement tables come
//! from the same `lower::Ir` as the C, and the protocol logic is a line-by-line transcription of
//! the runtime (`protocol_lattice.rs`, `protocol_paper.rs`: every inline names the C function it
//! mirrors). Around it, the environment: links that deliver the sender's current copy at any
//! time or never, a bounded number of stale packets delivered late (and again), actuators that
//! finish after an unknown time, and a bounded number of module resets at any moment.
//!
//! Ghost variables record what happened physically (started and done operations, per epoch)
//! and the checks of the simulator (`dynarole-sim`, `ops.rs`) are assertions: S1 at every first
//! start, S2 at every re-issue, S3 when a module first declares the end. L is the LTL formula
//! `finishes` (`<>[]` every module knows the end), checked with weak fairness. The model prints
//! one `@` event line per step that matters, which `dynarole verify` reads back from spin's
//! replay of a counterexample.
//!
//! **API boundary**: the caller passes the communication graph ([`Topology`]); this crate
//! knows nothing of geometry.

#[path = "promela/compositional.rs"]
mod compositional;
#[path = "promela/lattice.rs"]
mod lattice;
#[path = "promela/paper.rs"]
mod paper;

pub use compositional::{liveness_graph, LivenessGraph};

use crate::options::CompileOptions;
use crate::paper::pending_slots;
use crate::protocol::Protocol;
use dynarole_core::lower::{Ir, LimitError, PAPER_STATE_END};
use dynarole_core::span::Span;
use std::fmt::Write;

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
    let protocol = options.compile.protocol.info();
    if !protocol.modelled {
        return Err(limit(format!(
            "the model checker models {}, not the {}",
            Protocol::modelled_in_words(),
            protocol.description
        )));
    }
    if ir.statements.is_empty() {
        return Err(limit("the model needs at least one statement".into()));
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
    if options.compile.protocol == Protocol::Lattice && ir.window > MAX_MODEL_WINDOW {
        return Err(limit(format!(
            "the model encodes lattice windows up to {MAX_MODEL_WINDOW} statements; this sequence needs {}",
            ir.window
        )));
    }
    if options.compile.protocol == Protocol::Lattice && options.compile.epochs == 0 {
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
        Protocol::Token => return Err(limit("the token baseline is not modelled".into())),
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
    if o.protocol != Protocol::Lattice || o.no_nv {
        return Err(limit(
            "the compositional model is for the lattice protocol with NV storage".into(),
        ));
    }
    if o.epochs != 1 {
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
        match self.options.compile.protocol {
            Protocol::Lattice => usize::from(self.options.compile.epochs.max(1)),
            Protocol::Paper | Protocol::Token => 1,
        }
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

    fn header(&self, out: &mut String) {
        let o = &self.options.compile;
        let protocol = o.describe();
        let _ = writeln!(
            out,
            "/* dynarole model of {} for robot {} ({protocol}), generated by dynarole;\n * do not edit. Check with `dynarole verify`, or: spin -a model.pml && cc -DSAFETY -DNOCLAIM\n * -o pan pan.c && ./pan (safety), cc -DNOREDUCE -o pan pan.c && ./pan -a -f (liveness; add\n * -DLIVENESS to spin). */\n",
            o.name, self.ir.robot
        );
        out.push_str("/* Statements (index, module address, text):\n");
        for (i, s) in self.ir.statements.iter().enumerate() {
            let _ = writeln!(out, " *   {i:>3}  {:>3}  {}", s.address, s.text);
        }
        out.push_str(" * Modules (index, name, address):\n");
        for (k, m) in self.topology.modules.iter().enumerate() {
            let address = m.address.map_or("-".to_string(), |a| a.to_string());
            let _ = writeln!(out, " *   {k:>3}  {}  {address}", m.name);
        }
        out.push_str(
            " * Links (from -> to; stages in which they are assumed to deliver eventually):\n",
        );
        for l in &self.topology.links {
            let _ = writeln!(
                out,
                " *   {} -> {}  {}",
                l.from,
                l.to,
                stage_condition(&l.fair_stages)
            );
        }
        out.push_str(" */\n\n");
        let _ = writeln!(out, "#define N_STATEMENTS {}", self.n());
        let _ = writeln!(out, "#define N_MODULES {}", self.m());
        let _ = writeln!(out, "#define N_EPOCHS {}", self.epochs());
        let _ = writeln!(out, "#define RESETS {}", self.options.resets);
        let _ = writeln!(out, "#define LATE {}", self.options.late);
        out.push_str("#define NONE 255\n#define NO_ADDRESS 255\n#define MANY_ADDRESSES 254\n\n");
        let addr = self.per_module("m", |k| {
            self.topology.modules[k]
                .address
                .map_or("NO_ADDRESS".to_string(), |a| a.to_string())
        });
        let _ = writeln!(
            out,
            "/* The address of module m (the role predicates on the configuration). */\n#define ADDR(m) {addr}"
        );
        self.tables(out);
        // A number: FINISHED is used before the paper model defines its STATE_END.
        let finished = match self.options.compile.protocol {
            Protocol::Lattice => "(epoch[m] >= N_EPOCHS)".to_string(),
            Protocol::Paper | Protocol::Token => format!("(g_state[m] == {PAPER_STATE_END})"),
        };
        let _ = writeln!(
            out,
            "/* dr_module_finished(m): the module knows the end. */\n#define FINISHED(m) {finished}\n"
        );
        self.ghosts(out);
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
                "what it waits for (dr_program_deps: deps and the module's previous statement)",
                of(&|st| st.waits_for()),
            ),
        ]
    }

    /// The statement tables, as hidden (constant, not part of the state) arrays filled once at
    /// the start ([`Gen::table_steps`]): each statement's address, and three lists per statement
    /// (its dependencies, its transitive dependents, what it waits for). Loops over them keep
    /// the verifier's code small whatever the number of statements.
    fn tables(&self, out: &mut String) {
        out.push_str("/* The address of statement s (dr_statement_t.address). */\nhidden byte st_addr[N_STATEMENTS];\n#define ST_ADDR(s) st_addr[s]\n");
        for (name, what, lists) in &self.table_lists() {
            let total: usize = lists.iter().map(Vec::len).sum();
            let _ = writeln!(
                out,
                "/* Statement s's {what}: {name}_list[{name}_first[s] .. {name}_first[s + 1]). */\nhidden short {name}_first[N_STATEMENTS + 1];\nhidden byte {name}_list[{}];",
                total.max(1)
            );
        }
        out.push('\n');
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

    /// Ghost state and the S1-S3 checks (the simulator's, `dynarole-sim` `ops.rs`).
    fn ghosts(&self, out: &mut String) {
        let n = self.n();
        out.push_str(
            "/* ---- Ghost state: what happened physically (not seen by the modules) ---- */\n",
        );
        out.push_str(
            "bit g_started[N_EPOCHS * N_STATEMENTS]; /* issued at least once, per epoch */\n",
        );
        out.push_str("bit g_done[N_EPOCHS * N_STATEMENTS];    /* physically done, per epoch */\n");
        out.push_str(
            "bit p_run[N_STATEMENTS];                /* the operation is running now */\n",
        );
        if self.epochs() > 1 {
            out.push_str(
                "byte p_epoch[N_STATEMENTS];             /* the epoch it was issued in */\n",
            );
        }
        out.push_str("bit declared[N_MODULES];                /* the module declared the end */\n");
        out.push_str("#ifdef LIVENESS\nbyte stage;  /* statements 0..stage-1 physically done (epoch 0), stage not */\n#endif\n");
        out.push_str("hidden byte t_ok;\nhidden int t_i, t_j, t_k, t_s, t_x, t_y;\n\n");
        // S1: the IR's dependencies (what the sequence means), physically done.
        out.push_str("/* S1 (ops.rs check_dependencies): every dependency of s is physically done in epoch e\n * (and, for e > 0, the whole previous epoch). Sets t_ok. */\n");
        out.push_str("inline deps_physically_done(s, e) {\n    t_ok = 1;\n    t_x = deps_first[s];\n    do\n    :: t_x < deps_first[s + 1] -> t_ok = t_ok && g_done[e * N_STATEMENTS + deps_list[t_x]]; t_x++\n    :: else -> break\n    od;\n");
        if self.epochs() > 1 {
            out.push_str("    t_j = 0;\n    do\n    :: e > 0 && t_j < N_STATEMENTS -> t_ok = t_ok && g_done[(e - 1) * N_STATEMENTS + t_j]; t_j++\n    :: else -> break\n    od\n");
        }
        out.push_str("}\n\n");
        // S2: transitive dependents through the IR's deps (sequence.rs `dependents`).
        out.push_str("/* S2 (ops.rs check_not_overtaken): no statement that depends on s (transitively) has\n * started in epoch e, and nothing of a later epoch has. Sets t_ok. */\n");
        out.push_str("inline none_overtaken(s, e) {\n    t_ok = 1;\n    t_x = dependents_first[s];\n    do\n    :: t_x < dependents_first[s + 1] -> t_ok = t_ok && !g_started[e * N_STATEMENTS + dependents_list[t_x]]; t_x++\n    :: else -> break\n    od;\n");

        if self.epochs() > 1 {
            out.push_str("    t_j = (e + 1) * N_STATEMENTS;\n    do\n    :: t_j < N_EPOCHS * N_STATEMENTS -> t_ok = t_ok && !g_started[t_j]; t_j++\n    :: else -> break\n    od\n");
        }
        out.push_str("}\n\n");
        out.push_str("/* dr_hal_op_start as the environment sees it: module m starts statement s's operation in\n * epoch e (the protocol's epoch; 0 for the paper protocol). First start: S1; again: S2. */\n");
        out.push_str("inline issue(m, s, e) {\n    printf(\"@issue %d %d %d\\n\", m, s, e);\n    if\n    :: !g_started[e * N_STATEMENTS + s] ->\n        deps_physically_done(s, e);\n        if\n        :: !t_ok -> printf(\"@violation S1 %d %d\\n\", m, s); assert(false)\n        :: else -> skip\n        fi;\n        g_started[e * N_STATEMENTS + s] = 1\n    :: else ->\n        none_overtaken(s, e);\n        if\n        :: !t_ok -> printf(\"@violation S2 %d %d\\n\", m, s); assert(false)\n        :: else -> skip\n        fi\n    fi;\n");
        if self.epochs() > 1 {
            out.push_str("    p_epoch[s] = e;\n");
        }
        out.push_str("    p_run[s] = 1\n}\n\n");
        let all_done: Vec<String> = (0..self.epochs() * n)
            .map(|k| format!("g_done[{k}]"))
            .collect();
        let none_running: Vec<String> = (0..n).map(|s| format!("!p_run[{s}]")).collect();
        let _ = writeln!(
            out,
            "#define ALL_DONE ({})\n#define NONE_RUNNING ({})\n",
            all_done.join(" && "),
            none_running.join(" && ")
        );
        out.push_str("/* S3 (ops.rs check_end): when module m first declares the end, every operation of every\n * epoch is done and none runs. */\ninline end_check(m) {\n    if\n    :: FINISHED(m) && !declared[m] ->\n        declared[m] = 1;\n        printf(\"@end %d\\n\", m);\n        if\n        :: !(ALL_DONE && NONE_RUNNING) -> printf(\"@violation S3 %d 0\\n\", m); assert(false)\n        :: else -> skip\n        fi\n    :: else -> skip\n    fi\n}\n\n");
        // Module busy: the HAL's dr_hal_op_status (ops.rs op_status: running while any
        // operation the module started runs).
        let busy = self.per_module("m", |k| {
            let mine: Vec<String> = self
                .statements_of(k)
                .iter()
                .map(|s| format!("p_run[{s}]"))
                .collect();
            if mine.is_empty() {
                "0".into()
            } else {
                format!("({})", mine.join(" || "))
            }
        });
        let _ = writeln!(
            out,
            "/* dr_hal_op_status(m) == DR_OP_RUNNING: an operation module m started still runs. */\n#define BUSY(m) {busy}\n"
        );
        out.push_str("/* The stage (for the links' fairness): the longest done prefix of statements. */\ninline advance_stage() {\n#ifdef LIVENESS\n    do\n    :: stage < N_STATEMENTS && g_done[stage] -> stage++\n    :: else -> break\n    od;\n    skip /* the break must land inside the d_step */\n#else\n    skip\n#endif\n}\n\n");
        out.push_str("/* A reset stops module m's actuators: a running operation is interrupted (not done). */\ninline interrupt(m) {\n    if\n");
        for k in 0..self.m() {
            let mine: Vec<String> = self
                .statements_of(k)
                .iter()
                .map(|s| format!("p_run[{s}] = 0"))
                .collect();
            if !mine.is_empty() {
                let _ = writeln!(out, "    :: m == {k} -> {}", mine.join("; "));
            }
        }
        out.push_str("    :: else -> skip\n    fi\n}\n\n");
    }

    /// Module, link, actuator, late-packet and reset processes, the LTL property, and `init`.
    fn processes(&self, out: &mut String, fill: &str) {
        out.push_str("/* ---- Processes ---- */\n");
        for k in 0..self.m() {
            let _ = writeln!(
                out,
                "/* Module {k} ({}): dr_module_step, one call per step. */\nproctype module_{k}() {{\n    do\n    :: d_step {{ step({k}); print_copy({k}) }}\n    od\n}}\n",
                self.topology.modules[k].name
            );
        }
        out.push_str("#ifdef LIVENESS\n/* Any link at any time, unfairly (a link may deliver outside the stages where it surely\n * exists, never must): one process, so that its steps stand for no module's or link's. */\nproctype radio() {\n    do\n");
        for l in &self.topology.links {
            let _ = writeln!(out, "    :: d_step {{ deliver({}, {}) }}", l.from, l.to);
        }
        out.push_str("    od\n}\n#endif\n\n");
        let adaptive = self.options.compile.protocol == Protocol::Lattice
            && self.options.compile.dissemination == crate::protocol::Dissemination::Adaptive;
        for l in &self.topology.links {
            let mut up = stage_condition(&l.fair_stages);
            if adaptive {
                // Adaptive dissemination: only deliveries that carry something are owed.
                let _ = write!(up, " && WANTS({}, {})", l.from, l.to);
            }
            let _ = writeln!(
                out,
                "/* The link {} -> {}: delivers the sender's current copy at any time (a packet not\n * delivered yet is a lost one). With LIVENESS: only in the stages where the link surely\n * exists, and then eventually (weak fairness). */\nproctype link_{}_{}() {{\n    do\n#ifdef LIVENESS\n    :: d_step {{ {up} -> deliver({}, {}) }}\n#else\n    :: d_step {{ deliver({}, {}) }}\n#endif\n    od\n}}\n",
                l.from, l.to, l.from, l.to, l.from, l.to, l.from, l.to
            );
        }
        self.actuators(out, |_| true);
        if self.options.resets > 0 {
            out.push_str("/* Resets: at most RESETS, of any module, at any moment between two of its steps (in the\n * middle of an operation too); the process may also stop resetting at any time. */\nproctype resets() {\n    byte left = RESETS;\n    do\n");
            for k in 0..self.m() {
                if !self.options.reset_modules.is_empty()
                    && !self.options.reset_modules.contains(&k)
                {
                    continue;
                }
                let _ = writeln!(
                    out,
                    "    :: left > 0 {} -> d_step {{ left--; printf(\"@reset {k}\\n\"); reset({k}) }}",
                    self.reset_guard(k)
                );
            }
            out.push_str("    :: break\n    od\n}\n\n");
        }
        if self.options.late > 0 {
            self.late_process(out);
        }
        let finished: Vec<String> = (0..self.m()).map(|k| format!("FINISHED({k})")).collect();
        let _ = writeln!(
            out,
            "/* L: eventually every module knows the end, for good. */\nltl finishes {{ <> [] ({}) }}\n",
            finished.join(" && ")
        );
        let _ = write!(
            out,
            "init {{\n{}    d_step {{ initialise() }};\n    atomic {{\n",
            self.table_steps(fill)
        );
        for k in 0..self.m() {
            let _ = writeln!(out, "        run module_{k}();");
        }
        for l in &self.topology.links {
            let _ = writeln!(out, "        run link_{}_{}();", l.from, l.to);
        }
        for k in 0..self.m() {
            if !self.statements_of(k).is_empty() {
                let _ = writeln!(out, "        run actuator_{k}();");
            }
        }
        if self.options.resets > 0 {
            out.push_str("        run resets();\n");
        }
        out.push_str("#ifdef LIVENESS\n        run radio();\n#endif\n");
        if self.options.late > 0 {
            out.push_str("        run late();\n");
        }
        out.push_str("    }\n}\n");
    }

    /// One process per module with statements (the modules in `which`): a started operation
    /// finishes after an unknown time.
    pub fn actuators(&self, out: &mut String, which: impl Fn(usize) -> bool) {
        for k in (0..self.m()).filter(|&k| which(k)) {
            let mine = self.statements_of(k);
            if mine.is_empty() {
                continue;
            }
            let _ = writeln!(
                out,
                "/* Module {k}'s actuators: a started operation finishes after an unknown time. */\nproctype actuator_{k}() {{\n    do"
            );
            for s in mine {
                let _ = writeln!(out, "{}", self.finish_branch(k, s));
            }
            out.push_str("    od\n}\n\n");
        }
    }

    /// The `do` branch in which module k's operation of statement s finishes (physically).
    pub fn finish_branch(&self, k: usize, s: usize) -> String {
        let epoch = if self.epochs() > 1 {
            format!("p_epoch[{s}]")
        } else {
            "0".into()
        };
        format!("    :: d_step {{ p_run[{s}] -> p_run[{s}] = 0; g_done[{epoch} * N_STATEMENTS + {s}] = 1; printf(\"@done {k} {s}\\n\"); advance_stage() }}")
    }

    /// With the lattice's no-NV rules, assumption (a) of runtime/lattice/README.md: a module
    /// resets only when every module that reset before has heard all its neighbours.
    fn reset_guard(&self, _k: usize) -> String {
        if self.options.compile.protocol == Protocol::Lattice && self.options.compile.no_nv {
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
        out.push_str("/* Late packets: a slot takes a copy of a sender's state (a packet sent now) and may deliver it\n * at any later time, again and again (delay, duplication, reordering), or drop it. */\n");
        out.push_str(
            "proctype late() {\n#ifdef LIVENESS\n    byte budget = LATE;\n#endif\n    do\n",
        );
        let guard = "#ifdef LIVENESS\n        budget > 0 &&\n#endif\n";
        for slot in 0..usize::from(self.options.late) {
            for (j, l) in self.topology.links.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "    :: d_step {{\n{guard}        !l_full[{slot}] -> capture({slot}, {}, {});\n#ifdef LIVENESS\n        budget--;\n#endif\n        printf(\"@capture {slot} {} {}\\n\", {}, {})\n    }}",
                    l.from, l.to, l.from, l.to, l.from, l.to
                );
                let _ = j;
            }
            let _ = writeln!(
                out,
                "    :: d_step {{ l_full[{slot}] -> printf(\"@late {slot} %d %d\\n\", l_from[{slot}], l_to[{slot}]); deliver_late({slot});\n#ifdef LIVENESS\n        l_full[{slot}] = 0\n#endif\n    }}\n    :: d_step {{ l_full[{slot}] -> l_full[{slot}] = 0 }}"
            );
        }
        out.push_str("    od\n}\n\n");
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
