//! The Promela back-end on its own: snapshots of the full and the compositional model of
//! protocol.md's `A & B; C;` on three modules in a line, where the links for L are found or
//! missed, and what the compositional model refuses. (Running spin on them is
//! `dynarole-cli`'s `tests/verify.rs`.)

use dynarole_codegen::{
    generate_compositional, generate_promela, liveness_graph, CompileOptions, ModelOptions,
    Protocol, Topology, TopologyLink, TopologyModule,
};
use dynarole_core::lower::Ir;

#[path = "../src/promela/test_support.rs"]
mod test_support;
use test_support::{line, lowered};

const AB_C: &str = include_str!("../../../robots/atron/examples/verify/ab_c.dr");

fn ir() -> Ir {
    lowered(AB_C, "ab_c")
}

/// The options of the model of `ab_c`.
fn options(protocol: Protocol, late: u8) -> ModelOptions {
    test_support::options("ab_c", protocol, late)
}

#[test]
fn full_model_of_ab_c() {
    let model = generate_promela(&ir(), &line(&[0, 1, 2, 3]), &options(Protocol::Lattice, 1))
        .expect("models");
    assert_eq!(model.module_names, ["M0", "M1", "M2"]);
    insta::assert_snapshot!(
        "full_lattice_ab_c",
        format!(
            "{AB_C}\n----- model.pml (full, lattice, 1 reset, 1 late) -----\n{}",
            model.text
        )
    );
}

#[test]
fn compositional_model_of_ab_c_checks_one_module() {
    let ir = ir();
    let topology = line(&[0, 1, 2, 3]);
    let graph = liveness_graph(&ir, &topology);
    let model = generate_compositional(&ir, &topology, &options(Protocol::Lattice, 0), 1, &graph)
        .expect("models");
    // Only M1 runs the protocol's logic; M0 and M2 are reduced to their start rule.
    assert!(model.text.contains("proctype module_1()"));
    assert!(!model.text.contains("proctype module_0()"));
    assert!(model.text.contains("proctype env_0()") && model.text.contains("proctype env_2()"));
    // ↓#2 is {0, 1, 2}: the whole prefix, low 3.
    assert!(model.text.contains("t_rec[2] -> hear(0, 3, 0)"));
    insta::assert_snapshot!(
        "compositional_lattice_ab_c_m1",
        format!(
            "{AB_C}\n----- model-M1.pml (compositional, lattice, 1 reset) -----\n{}",
            model.text
        )
    );
}

#[test]
fn links_that_always_exist_carry_everything_l_needs() {
    let graph = liveness_graph(&ir(), &line(&[0, 1, 2, 3]));
    assert!(graph.stuck_statements().is_empty());
    assert!(graph.deaf_modules().is_empty());
    // #2 on M2 waits for #0 (M0) and #1 (M1): carried in every stage.
    assert_eq!(graph.statement_stages[2], [0, 1, 2, 3]);
}

#[test]
fn links_missing_in_a_stage_leave_l_unestablished() {
    // The links exist only in stages 0 and 1: #2 (stage 2) cannot hear what it waits for, and
    // nobody can be shown to hear the end (stage 3).
    let graph = liveness_graph(&ir(), &line(&[0, 1]));
    assert_eq!(graph.stuck_statements(), [2]);
    assert_eq!(graph.deaf_modules(), [0, 1, 2]);
}

#[test]
fn compositional_model_is_for_the_lattice_protocol_with_nv_and_without_late_slots() {
    let ir = ir();
    let topology = line(&[0, 1, 2, 3]);
    let graph = liveness_graph(&ir, &topology);
    let paper = generate_compositional(&ir, &topology, &options(Protocol::Paper, 0), 0, &graph);
    assert!(paper
        .expect_err("refused")
        .message
        .contains("lattice protocol with NV"));
    let mut no_nv = options(Protocol::Lattice, 0);
    no_nv.compile.no_nv = true;
    let refused = generate_compositional(&ir, &topology, &no_nv, 0, &graph);
    assert!(refused
        .expect_err("refused")
        .message
        .contains("lattice protocol with NV"));
    let late = generate_compositional(&ir, &topology, &options(Protocol::Lattice, 1), 0, &graph);
    assert!(late.expect_err("refused").message.contains("late-packet"));
}

/// The paper model's step is the same code whatever the sequence (the switch is tables read
/// by one inline), so a long sequence stays within spin's limit on a `d_step`; the tables
/// carry the layout.
#[test]
fn the_paper_switch_is_tables_so_a_step_does_not_grow_with_the_sequence() {
    let long = "robot atron;\nsequence long {\n".to_string()
        + &"    M0.Joint.rotateFromToBy(0, 108, true, 150) &\n    M1.Joint.rotateFromToBy(0, 108, true, 150);\n    M2.Joint.rotateFromToBy(0, 108, true, 150);\n".repeat(10)
        + "}\n";
    let long_ir = lowered(&long, "long");
    let topology = line(&[0, 1, 2, 3]);
    let short = generate_promela(&ir(), &topology, &options(Protocol::Paper, 1)).expect("models");
    let long = generate_promela(&long_ir, &topology, &options(Protocol::Paper, 1)).expect("models");
    let step = |text: &str| -> String {
        let from = text.find("inline program_step(m)").expect("a step");
        let to = from + text[from..].find("\n}\n").expect("its end");
        text[from..to].to_string()
    };
    assert_eq!(step(&short.text), step(&long.text));
    // 30 statements: 10 parallel units (3 states) and 20 sequential ones (2), from state 1.
    assert!(long.text.contains("#define SW_STATES 71"), "{}", long.text);
    assert!(long.text.contains("sw_issue[29] = 29;"));
    assert_eq!(long.paper_states.len(), 30);
    // init: the table d_steps, initialise, and one `run` per process.
    let runs = long.text.matches("        run ").count();
    let fills = long.text.matches("    d_step {\n").count();
    assert_eq!(long.init_steps, runs + fills + 1);
}

/// Every model the options can ask for: each template part is filled with exactly its holes
/// (a mismatch stops a debug build), and every `printf` the model has is an event of the trail
/// vocabulary that reads back as its kind once spin has printed it.
#[test]
fn every_option_fills_every_template_and_prints_only_the_vocabulary() {
    use dynarole_codegen::trail_events::{parse_printed, EVENTS};
    use dynarole_codegen::{Dissemination, Fault, PaperMerge};
    let ir = ir();
    let topology = line(&[0, 2, 3]);
    let graph = liveness_graph(&ir, &topology);
    let mut models = Vec::new();
    for (no_nv, resets, late) in [(false, 0, 0), (false, 1, 1), (true, 1, 2), (true, 0, 0)] {
        for epochs in [1, 2] {
            for dissemination in [Dissemination::Adaptive, Dissemination::Fixed] {
                for fault in [None, Some(Fault::JoinDropsDone), Some(Fault::JoinNoRebase)] {
                    let mut o = options(Protocol::Lattice, late);
                    o.resets = resets;
                    o.fault = fault;
                    o.compile.no_nv = no_nv;
                    o.compile.epochs = epochs;
                    o.compile.dissemination = dissemination;
                    models.push(generate_promela(&ir, &topology, &o));
                    for c in 0..3 {
                        models.push(generate_compositional(&ir, &topology, &o, c, &graph));
                    }
                }
            }
        }
    }
    for merge in [PaperMerge::Printed, PaperMerge::Java, PaperMerge::CPort] {
        for (single_step_handover, restart_pending, late) in [(false, false, 0), (true, true, 2)] {
            let mut o = options(Protocol::Paper, late);
            o.compile.merge = merge;
            o.compile.single_step_handover = single_step_handover;
            o.compile.restart_pending = restart_pending;
            models.push(generate_promela(&ir, &topology, &o));
        }
    }
    let mut printed = std::collections::BTreeSet::new();
    for model in models.into_iter().flatten() {
        assert!(!model.text.contains("{{") && !model.text.contains("#error"));
        for statement in model.text.split("printf(\"").skip(1) {
            let (format, rest) = statement.split_once("\\n\"").expect("a format");
            let args = rest.split(')').next().unwrap_or("").matches(',').count();
            assert_eq!(format.matches("%d").count(), args, "{format}");
            // What spin prints: a number for each `%d`.
            let line = format.replace("%d", "3");
            let event = parse_printed(&line).unwrap_or_else(|| panic!("not an event: {line}"));
            assert_eq!(
                format!("@{}", event.kind.spec().name),
                format.split(' ').next().unwrap_or("")
            );
            printed.insert(event.kind.spec().name);
        }
    }
    // And the models print every event of the vocabulary.
    let names: std::collections::BTreeSet<&str> = EVENTS.iter().map(|e| e.name).collect();
    assert_eq!(printed, names);
}
