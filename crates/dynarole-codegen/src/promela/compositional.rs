//! The compositional model of the lattice protocol: one module's logic, exactly as in the
//! full model, against an abstract robot in which every packet is any state the robot has
//! already reached (`dynarole verify --method compositional`); the Promela is the template
//! `runtime/lattice/dr_lattice_compositional.pml`, around `dr_lattice.pml`.
//!
//! Why it is sound (docs/verification.md has the argument in full): call the truth T the join
//! of every copy any module ever held. Every packet, every NV record and every copy is below
//! T, and is closed under dependencies (a statement is only ever marked done by the module that
//! completed it, which started it when its copy held everything it waits for). So a module can
//! receive at any time any dependency-closed state below T, which is the join of the states
//! `↓s` (s and everything it depends on, transitively) for s in T: the model delivers those,
//! one at a time, in any order, again and again. The other modules are reduced to their start
//! rule (a statement not in T whose dependencies are all in T, several at once as a batch
//! runs them, or one at a time), their actuators and their resets. The module under check must in turn guarantee what the others were
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

use super::events::{expr, printf, value, Arg, EventKind};
use super::template::{Holes, TemplateFile};
use super::{stage_condition, Gen, Topology};
use dynarole_core::lower::Ir;
use std::collections::{BTreeSet, VecDeque};

/// The abstract robot around the checked module: `runtime/lattice/dr_lattice_compositional.pml`.
pub(super) static COMPOSITIONAL: TemplateFile = TemplateFile {
    path: "runtime/lattice/dr_lattice_compositional.pml",
    text: include_str!("../../../../runtime/lattice/dr_lattice_compositional.pml"),
};

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
    let (m, s) = (expr("m"), expr("s"));
    let violation = |p: &str, s: Arg| printf(EventKind::Violation, &[value(p), expr("m"), s]);
    let holes = Holes::new()
        .text("print_record", printf(EventKind::Record, &[m, s.clone()]))
        .text("print_g4", violation("G4", s));
    out.push_str(&COMPOSITIONAL.part("truth").fill(&holes));
    super::lattice::write(g, out);
    let holes = Holes::new()
        .text("print_g1_end", violation("G1", value(0)))
        .text("print_g1", violation("G1", expr("t_j")))
        .text("print_g2", violation("G2", expr("t_j")))
        .text("print_g3", violation("G3", expr("t_j")));
    out.push_str(&COMPOSITIONAL.part("guarantee").fill(&holes));
    let holes = Holes::new()
        .text("c", c)
        .text("name", &g.topology.modules[c].name);
    out.push_str(&COMPOSITIONAL.part("module").fill(&holes));
    news(g, out, c);
    fair_news(g, out, c, graph);
    environment(g, out, c, graph);
    g.actuators(out, |k| k == c);
    resets(g, out, c);
    let mut runs: Vec<String> = (0..g.m())
        .filter(|&k| k != c && !g.statements_of(k).is_empty())
        .map(|k| format!("        run env_{k}();"))
        .collect();
    if !g.statements_of(c).is_empty() {
        runs.push(format!("        run actuator_{c}();"));
    }
    let others = (0..g.m()).any(|k| k != c && !g.statements_of(k).is_empty());
    let holes = Holes::new()
        .text("c", c)
        .text("tables", g.table_steps(""))
        .text("runs", runs.join("\n"))
        .flag("resets", g.options.resets > 0)
        .flag("others", others);
    out.push_str(&COMPOSITIONAL.part("init").fill(&holes));
}

/// Any dependency-closed state below T, as the join of the states `↓s`, s in T.
fn news(g: &Gen, out: &mut String, c: usize) {
    let mut seen = BTreeSet::new();
    let mut down_sets = Vec::new();
    for s in 0..g.n() {
        let (low, bits) = normal_form(&down_set(g.ir, s));
        if seen.insert((low, bits)) {
            down_sets.push(format!(
                "    :: d_step {{ t_rec[{s}] -> hear(0, {low}, {bits}) }} /* ↓#{s} */"
            ));
        }
    }
    let hear = [value(c), expr("e"), expr("l"), expr("d")];
    let holes = Holes::new()
        .text("c", c)
        .text("print_hear", printf(EventKind::Hear, &hear))
        .text("down_sets", down_sets.join("\n"));
    out.push_str(&COMPOSITIONAL.part("news").fill(&holes));
}

/// With LIVENESS: what the links that surely exist carry to module c, eventually.
fn fair_news(g: &Gen, out: &mut String, c: usize, graph: &LivenessGraph) {
    let mut branches = Vec::new();
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
        branches.push(format!(
            "    :: d_step {{ {stages} && epoch[{c}] < N_EPOCHS && !IS_DONE({c}, {s}) && {} && !({}) -> hear(0, {low}, {bits}) }} /* what #{s} waits for */",
            recorded.join(" && "),
            known.join(" && ")
        ));
    }
    let holes = Holes::new()
        .text("c", c)
        .text("waits", branches.join("\n"))
        .flag("end_reaches", graph.end_reaches[c]);
    out.push_str(&COMPOSITIONAL.part("fair_news").fill(&holes));
}

/// The other modules, reduced to their start rule, and their completions recorded in T.
fn environment(g: &Gen, out: &mut String, c: usize, graph: &LivenessGraph) {
    let start = |k: usize, s: usize| -> String {
        format!("!e_pend[{s}] && !t_end && !t_rec[{s}] && WAITS_RECORDED_{s} -> e_pend[{s}] = 1; issue({k}, {s}, 0)")
    };
    let defines: Vec<String> = (0..g.n())
        .map(|s| {
            let waits: Vec<String> = (g.ir.statements[s].waits_for().iter())
                .map(|d| format!("t_rec[{d}]"))
                .collect();
            let cond = if waits.is_empty() {
                "1".to_string()
            } else {
                format!("({})", waits.join(" && "))
            };
            format!("#define WAITS_RECORDED_{s} {cond}")
        })
        .collect();
    let holes = Holes::new().text("defines", defines.join("\n"));
    out.push_str(&COMPOSITIONAL.part("waits_recorded").fill(&holes));
    let mut radio = Vec::new();
    for k in 0..g.m() {
        let mine = g.statements_of(k);
        if k == c || mine.is_empty() {
            continue;
        }
        let mut starts = String::new();
        for &s in &mine {
            let stages = stage_condition(&graph.statement_stages[s]).replace("stage", "t_stage");
            let holes = Holes::new()
                .text("stages", stages)
                .text("start", start(k, s));
            starts.push_str(&COMPOSITIONAL.part("env_start").fill(&holes));
            radio.push(format!("    :: d_step {{ {} }}", start(k, s)));
        }
        let finishes: String = mine.iter().map(|&s| g.finish_branch(k, s)).collect();
        let records: Vec<String> = (mine.iter())
            .map(|&s| format!("    :: d_step {{ e_pend[{s}] && !p_run[{s}] -> record({k}, {s}); e_pend[{s}] = 0 }}"))
            .collect();
        let holes = Holes::new()
            .text("k", k)
            .text("name", &g.topology.modules[k].name)
            .text("starts", starts.trim_end())
            .text("finishes", finishes.trim_end())
            .text("records", records.join("\n"));
        out.push_str(&COMPOSITIONAL.part("env").fill(&holes));
    }
    if !radio.is_empty() {
        let holes = Holes::new().text("starts", radio.join("\n"));
        out.push_str(&COMPOSITIONAL.part("env_radio").fill(&holes));
    }
}

/// At most RESETS resets, of the checked module (its dr_module_init) or of another one (its
/// operation is interrupted and not recorded).
fn resets(g: &Gen, out: &mut String, c: usize) {
    if g.options.resets == 0 {
        return;
    }
    let mut branches = Vec::new();
    for k in 0..g.m() {
        if !g.options.reset_modules.is_empty() && !g.options.reset_modules.contains(&k) {
            continue;
        }
        let reset = printf(EventKind::Reset, &[value(k)]);
        if k == c {
            branches.push(format!(
                "    :: left > 0 -> d_step {{ left--; {reset}; reset({k}); print_copy({k}); guarantee({k}) }}"
            ));
        } else if !g.statements_of(k).is_empty() {
            let forget: Vec<String> = (g.statements_of(k).iter())
                .map(|s| format!("e_pend[{s}] = 0"))
                .collect();
            branches.push(format!(
                "    :: left > 0 -> d_step {{ left--; {reset}; interrupt({k}); {} }}",
                forget.join("; ")
            ));
        }
    }
    let holes = Holes::new().text("resets", branches.join("\n"));
    out.push_str(&COMPOSITIONAL.part("resets").fill(&holes));
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
