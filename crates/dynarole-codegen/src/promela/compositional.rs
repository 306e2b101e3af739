//! The compositional model of the lattice protocol: one module's logic, exactly as in the
//! full model, against an abstract robot in which every packet is any state the robot has
//! already reached (`dynarole verify --method compositional`).
//!
//! Why it is sound (docs/verification.md has the argument in full): call the truth T the join
//! of every copy any module ever held. Every packet, every NV record and every copy is below
//! T, and is closed under dependencies (a statement is only ever marked done by the module that
//! completed it, which started it when its copy held everything it waits for). So a module can
//! receive at any time any dependency-closed state below T, which is the join of the states
//! `↓s` (s and everything it depends on, transitively) for s in T: the model delivers those,
//! one at a time, in any order, again and again. The other modules are reduced to their start
//! rule (a statement not in T whose dependencies are all in T, one at a time), their actuators
//! and their resets. The module under check must in turn guarantee what the others were
//! assumed to do (its copy stays below T and dependency-closed, keeps its own completions, and
//! marks done only what is physically done): G1-G4, checked as assertions. Checking every
//! module this way proves S1-S3 for the whole robot, for any topology and any loss, delay,
//! duplication or reordering of packets.
//!
//! For L, delivery is made fair only where the links that surely exist carry it
//! ([`LivenessGraph`]): in stage k (statements 0..k recorded, k not), a module is eventually
//! told the dependencies of its statement s when every module that completes one of them
//! reaches it over links that surely exist in stage k; and it is eventually told the end when
//! every module that runs statements reaches it in the final configuration.

use super::{stage_condition, Gen, Topology};
use dynarole_core::lower::Ir;
use std::collections::{BTreeSet, VecDeque};
use std::fmt::Write;

/// Where the links that surely exist carry what the modules need to know (for L).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LivenessGraph {
    /// For each statement: the stages in which every module that runs one of its
    /// dependencies reaches the statement's module over links that surely exist.
    pub statement_stages: Vec<Vec<usize>>,
    /// For each module: every module that runs statements reaches it in the last stage.
    pub end_reaches: Vec<bool>,
}

impl LivenessGraph {
    /// Statements that cannot be shown to become startable in their own stage (stage s for
    /// statement s: everything before it is recorded).
    pub fn stuck_statements(&self) -> Vec<usize> {
        (0..self.statement_stages.len())
            .filter(|&s| !self.statement_stages[s].contains(&s))
            .collect()
    }

    /// Modules that cannot be shown to hear the end.
    pub fn deaf_modules(&self) -> Vec<usize> {
        (0..self.end_reaches.len())
            .filter(|&m| !self.end_reaches[m])
            .collect()
    }
}

/// The module (index into `topology.modules`) that runs each statement.
fn owners(ir: &Ir, topology: &Topology) -> Vec<Option<usize>> {
    ir.statements
        .iter()
        .map(|st| {
            topology
                .modules
                .iter()
                .position(|m| m.address == Some(st.address))
        })
        .collect()
}

/// Modules reachable from `from` over the links that surely exist in `stage`.
fn reachable(topology: &Topology, from: usize, stage: usize) -> Vec<bool> {
    let mut seen = vec![false; topology.modules.len()];
    let mut queue = VecDeque::from([from]);
    seen[from] = true;
    while let Some(m) = queue.pop_front() {
        for l in &topology.links {
            if l.from == m && !seen[l.to] && l.fair_stages.contains(&stage) {
                seen[l.to] = true;
                queue.push_back(l.to);
            }
        }
    }
    seen
}

/// Computes where the links that surely exist carry dependencies and the end.
pub fn liveness_graph(ir: &Ir, topology: &Topology) -> LivenessGraph {
    let n = ir.statements.len();
    let owner = owners(ir, topology);
    let reach: Vec<Vec<Vec<bool>>> = (0..=n)
        .map(|k| {
            (0..topology.modules.len())
                .map(|m| reachable(topology, m, k))
                .collect()
        })
        .collect();
    let statement_stages = (0..n)
        .map(|s| {
            (0..=n)
                .filter(|&k| {
                    ir.statements[s].waits_for().iter().all(|&d| {
                        match (owner[usize::from(d)], owner[s]) {
                            (Some(from), Some(to)) => reach[k][from][to],
                            _ => false,
                        }
                    })
                })
                .collect()
        })
        .collect();
    let runners: BTreeSet<usize> = owner.iter().flatten().copied().collect();
    let end_reaches = (0..topology.modules.len())
        .map(|m| runners.iter().all(|&r| reach[n][r][m]))
        .collect();
    LivenessGraph {
        statement_stages,
        end_reaches,
    }
}

/// `s` and everything it waits for, transitively.
fn down_set(ir: &Ir, s: usize) -> BTreeSet<usize> {
    let mut set = BTreeSet::from([s]);
    let mut todo = vec![s];
    while let Some(t) = todo.pop() {
        for d in ir.statements[t].waits_for() {
            if set.insert(usize::from(d)) {
                todo.push(usize::from(d));
            }
        }
    }
    set
}

/// The lattice's canonical form of a set of done statements of epoch 0: (low, done bits).
fn normal_form(set: &BTreeSet<usize>) -> (usize, u64) {
    let low = (0..).find(|t| !set.contains(t)).unwrap_or(0);
    let bits = set
        .iter()
        .filter(|&&s| s > low)
        .fold(0u64, |acc, &s| acc | (1u64 << (s - low)));
    (low, bits)
}

pub(crate) fn write(g: &Gen, out: &mut String, c: usize, graph: &LivenessGraph) {
    truth(g, out);
    super::lattice::write(g, out);
    guarantee(g, out);
    let _ = writeln!(
        out,
        "/* ---- Processes (compositional: module {c}, {}, is the one checked) ---- */",
        g.topology.modules[c].name
    );
    let _ = writeln!(
        out,
        "/* Module {c}: dr_module_step, one call per step; then its guarantees. */\nproctype module_{c}() {{\n    do\n    :: d_step {{ step({c}); print_copy({c}); guarantee({c}) }}\n    od\n}}\n"
    );
    news(g, out, c);
    fair_news(g, out, c, graph);
    environment(g, out, c, graph);
    g.actuators(out, |k| k == c);
    resets(g, out, c);
    let _ = writeln!(
        out,
        "/* L: eventually module {c} knows the end, for good. */\nltl finishes {{ <> [] FINISHED({c}) }}\n"
    );
    let _ = write!(
        out,
        "init {{\n{}    d_step {{ initialise() }};\n    atomic {{\n",
        g.table_steps("")
    );
    let _ = writeln!(out, "        run module_{c}();\n        run news();");
    for k in 0..g.m() {
        if k != c && !g.statements_of(k).is_empty() {
            let _ = writeln!(out, "        run env_{k}();");
        }
    }
    if !g.statements_of(c).is_empty() {
        let _ = writeln!(out, "        run actuator_{c}();");
    }
    if g.options.resets > 0 {
        out.push_str("        run resets();\n");
    }
    let others = (0..g.m()).any(|k| k != c && !g.statements_of(k).is_empty());
    let radio = if others {
        "        run env_radio();\n"
    } else {
        ""
    };
    let _ = write!(
        out,
        "#ifdef LIVENESS\n        run fair_news();\n{radio}#endif\n    }}\n}}\n"
    );
}

/// The truth T, its stage, the environment's running statements, and `record`.
fn truth(g: &Gen, out: &mut String) {
    out.push_str(
        "/* ---- The truth T: the join of every copy any module ever held (ghost) ---- */\n",
    );
    out.push_str("bit t_rec[N_STATEMENTS];  /* recorded: some module's copy holds it done */\nbit t_end;                /* every statement recorded: T is in epoch 1 */\nbyte t_stage;             /* the first statement not recorded */\nbyte e_run[N_MODULES] = NONE; /* the other modules: statement running, or done and not\n                                 recorded yet (the module has not polled it) */\n\n");
    out.push_str("/* Every statement s waits for (dr_program_deps) is recorded. Sets t_ok. */\ninline waits_recorded(s) {\n    t_ok = 1;\n    t_y = waits_first[s];\n    do\n    :: t_y < waits_first[s + 1] -> t_ok = t_ok && t_rec[waits_list[t_y]]; t_y++\n    :: else -> break\n    od;\n    skip\n}\n\n");

    out.push_str("/* Module m marks s done in its copy: T takes it. G4: only what is physically done, and\n * only once everything it waits for is recorded. */\ninline record(m, s) {\n    printf(\"@record %d %d\\n\", m, s);\n    waits_recorded(s);\n    if\n    :: !g_done[s] || !t_ok -> printf(\"@violation G4 %d %d\\n\", m, s); assert(false)\n    :: else -> skip\n    fi;\n    t_rec[s] = 1;\n    do\n    :: t_stage < N_STATEMENTS && t_rec[t_stage] -> t_stage++\n    :: else -> break\n    od;\n    if\n    :: t_stage == N_STATEMENTS -> t_end = 1\n    :: else -> skip\n    fi\n}\n\n");
    let _ = g;
}

/// G1-G3 on the checked module's copy, after each of its steps and receptions.
fn guarantee(g: &Gen, out: &mut String) {
    let _ = g;
    out.push_str("/* What the module under check guarantees to the others (they were assumed to do the\n * same): G1 its copy is below T; G2 its copy is closed under dependencies; G3 its copy\n * keeps every statement it recorded itself. */\ninline guarantee(m) {\n    if\n    :: epoch[m] >= N_EPOCHS && !t_end -> printf(\"@violation G1 %d 0\\n\", m); assert(false)\n    :: else -> skip\n    fi;\n    t_j = 0;\n    do\n    :: t_j < N_STATEMENTS && epoch[m] < N_EPOCHS ->\n        if\n        :: IS_DONE(m, t_j) && !t_rec[t_j] -> printf(\"@violation G1 %d %d\\n\", m, t_j); assert(false)\n        :: else -> skip\n        fi;\n        if\n        :: IS_DONE(m, t_j) ->\n            deps_done(m, t_j);\n            if\n            :: !t_ok -> printf(\"@violation G2 %d %d\\n\", m, t_j); assert(false)\n            :: else -> skip\n            fi\n        :: else -> skip\n        fi;\n        if\n        :: ST_ADDR(t_j) == ADDR(m) && t_rec[t_j] && !IS_DONE(m, t_j) -> printf(\"@violation G3 %d %d\\n\", m, t_j); assert(false)\n        :: else -> skip\n        fi;\n        t_j++\n    :: else -> break\n    od;\n    skip /* the break must land inside the d_step */\n}\n\n");
}

/// `hear(...)`: module c receives a state; its parameters are the state's fields.
fn hear_inline(c: usize) -> String {
    format!("inline hear(e, l, d) {{\n    in_epoch = e;\n    in_low = l;\n    in_done = d;\n    printf(\"@hear {c} %d %d %d\\n\", e, l, d);\n    join({c});\n    end_check({c});\n    print_copy({c});\n    guarantee({c})\n}}\n\n")
}

/// Any dependency-closed state below T, as the join of the states `↓s`, s in T.
fn news(g: &Gen, out: &mut String, c: usize) {
    out.push_str("/* The checked module hears a packet holding the state (e, l, d) (dr_module_receive, then\n * its guarantees). */\n");
    out.push_str(&hear_inline(c));
    out.push_str("/* Any packet: any state below T that is closed under dependencies, i.e. the join of some\n * states ↓s (s and all it waits for, transitively) with s in T. Delivered one ↓s at a time,\n * in any order, any number of times, or never: losses, delays, duplicates, any topology. */\nproctype news() {\n    do\n");
    let mut seen = BTreeSet::new();
    for s in 0..g.n() {
        let (low, bits) = normal_form(&down_set(g.ir, s));
        if seen.insert((low, bits)) {
            let _ = writeln!(
                out,
                "    :: d_step {{ t_rec[{s}] -> hear(0, {low}, {bits}) }} /* ↓#{s} */"
            );
        }
    }
    out.push_str("    :: d_step { t_end -> hear(1, 0, 0) } /* the end */\n    od\n}\n\n");
}

/// With LIVENESS: what the links that surely exist carry to module c, eventually.
fn fair_news(g: &Gen, out: &mut String, c: usize, graph: &LivenessGraph) {
    out.push_str("#ifdef LIVENESS\n/* What the links that surely exist carry to the checked module, eventually (weak fairness): the\n * dependencies of its next statements in the stages where every module that runs one of them\n * reaches it, and the end when every module that runs statements reaches it at the end. */\nproctype fair_news() {\n    do\n");
    for s in g.statements_of(c) {
        let waits = g.ir.statements[s].waits_for();
        if waits.is_empty() {
            continue;
        }
        let mut set = BTreeSet::new();
        for d in &waits {
            set.extend(down_set(g.ir, usize::from(*d)));
        }
        let (low, bits) = normal_form(&set);
        let recorded: Vec<String> = waits.iter().map(|d| format!("t_rec[{d}]")).collect();
        let known: Vec<String> = waits.iter().map(|d| format!("IS_DONE({c}, {d})")).collect();
        let stages = stage_condition(&graph.statement_stages[s]).replace("stage", "t_stage");
        let _ = writeln!(
            out,
            "    :: d_step {{ {stages} && epoch[{c}] < N_EPOCHS && !IS_DONE({c}, {s}) && {} && !({}) -> hear(0, {low}, {bits}) }} /* what #{s} waits for */",
            recorded.join(" && "),
            known.join(" && ")
        );
    }
    if graph.end_reaches[c] {
        let _ = writeln!(
            out,
            "    :: d_step {{ t_end && epoch[{c}] < N_EPOCHS -> hear(1, 0, 0) }} /* the end */"
        );
    } else {
        out.push_str("    :: false -> skip /* nothing is carried surely */\n");
    }
    out.push_str("    od\n}\n#endif\n\n");
}

/// The other modules, reduced to their start rule, and their completions recorded in T.
fn environment(g: &Gen, out: &mut String, c: usize, graph: &LivenessGraph) {
    let start = |k: usize, s: usize| -> String {
        format!("e_run[{k}] == NONE && !t_end && !t_rec[{s}] && WAITS_RECORDED_{s} -> e_run[{k}] = {s}; issue({k}, {s}, 0)")
    };
    for s in 0..g.n() {
        let waits: Vec<String> = g.ir.statements[s]
            .waits_for()
            .iter()
            .map(|d| format!("t_rec[{d}]"))
            .collect();
        let cond = if waits.is_empty() {
            "1".to_string()
        } else {
            format!("({})", waits.join(" && "))
        };
        let _ = writeln!(out, "#define WAITS_RECORDED_{s} {cond}");
    }
    out.push('\n');
    let mut radio = String::new();
    for k in 0..g.m() {
        let mine = g.statements_of(k);
        if k == c || mine.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "/* Module {k} ({}), abstracted: it starts one of its statements that is not in T and\n * whose dependencies are all in T (its copy is below T and keeps its own completions),\n * the operation finishes after an unknown time (its actuator: one process with the module,\n * as only one of the three kinds of step is enabled at a time, which keeps weak fairness\n * per process exact), and it records the statement in T. With LIVENESS, a start is fair\n * only in the stages where the links that surely exist carry the dependencies to it. */\nproctype env_{k}() {{\n    do",
            g.topology.modules[k].name
        );
        for &s in &mine {
            let stages = stage_condition(&graph.statement_stages[s]).replace("stage", "t_stage");
            let _ = writeln!(
                out,
                "    :: d_step {{\n#ifdef LIVENESS\n        {stages} &&\n#endif\n        {} }}",
                start(k, s)
            );
            let _ = writeln!(radio, "    :: d_step {{ {} }}", start(k, s));
        }
        for &s in &mine {
            let _ = writeln!(out, "{}", g.finish_branch(k, s));
        }
        let _ = writeln!(
            out,
            "    :: d_step {{ e_run[{k}] != NONE && !p_run[e_run[{k}]] -> record({k}, e_run[{k}]); e_run[{k}] = NONE }}\n    od\n}}\n"
        );
    }
    if !radio.is_empty() {
        let _ = writeln!(
            out,
            "#ifdef LIVENESS\n/* Starts that no link that surely exists justifies (a link may still deliver): unfair. */\nproctype env_radio() {{\n    do\n{radio}    od\n}}\n#endif\n"
        );
    }
}

/// At most RESETS resets, of the checked module (its dr_module_init) or of another one (its
/// operation is interrupted and not recorded).
fn resets(g: &Gen, out: &mut String, c: usize) {
    if g.options.resets == 0 {
        return;
    }
    out.push_str("/* Resets: at most RESETS, of any module, at any moment (mid-operation too). */\nproctype resets() {\n    byte left = RESETS;\n    do\n");
    for k in 0..g.m() {
        if !g.options.reset_modules.is_empty() && !g.options.reset_modules.contains(&k) {
            continue;
        }
        if k == c {
            let _ = writeln!(
                out,
                "    :: left > 0 -> d_step {{ left--; printf(\"@reset {k}\\n\"); reset({k}); print_copy({k}); guarantee({k}) }}"
            );
        } else if !g.statements_of(k).is_empty() {
            let _ = writeln!(
                out,
                "    :: left > 0 -> d_step {{ left--; printf(\"@reset {k}\\n\"); interrupt({k}); e_run[{k}] = NONE }}"
            );
        }
    }
    out.push_str("    :: break\n    od\n}\n\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_form_moves_the_done_prefix_into_low() {
        assert_eq!(normal_form(&BTreeSet::from([0, 1, 3])), (2, 0b10));
        assert_eq!(normal_form(&BTreeSet::from([1])), (0, 0b10));
        assert_eq!(normal_form(&BTreeSet::from([0, 1, 2])), (3, 0));
    }
}
