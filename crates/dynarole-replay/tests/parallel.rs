//! `parallelise` on the paper's sequences and on random sequences generated on the models:
//! the output replays to the input's end, and every `&` it writes passes the independence
//! check, forwards and in the reverse.

use dynarole_core::{analyze, parse};
use dynarole_replay::{
    assign_modules, check_independence, check_independence_exhaustive, dependency_graph,
    group_checked_graph, parallelise, replay, FormKind, Layout, Parallelised, Request, RobotWorld,
};
use dynarole_robot_atron::generated::atron_chain_json;
use dynarole_robot_atron::World;
use dynarole_robot_mtran::{MtranJoint, MtranWorld};
use dynarole_world::{compare, Configuration};
use proptest::prelude::*;

const EIGHT2CAR: &str = include_str!("../../../robots/atron/examples/eight2car.dr");
const FIG5: &str = include_str!("../../../robots/atron/examples/fig5.dr");
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");
const CAR: &str = include_str!("../../../robots/atron/examples/car.json");
const SNAKE: &str = include_str!("../../../robots/atron/examples/snake.json");

/// An ATRON structure to draw moves on: a chain of 3 to 7 modules, or one of the paper's
/// seven-module shapes (which have loops, so latches can be made and released).
fn atron_structure(pick: usize, longer: usize) -> (String, usize) {
    match pick % 8 {
        5 => (EIGHT.to_string(), 7),
        6 => (CAR.to_string(), 7),
        7 => (SNAKE.to_string(), 7),
        n => (atron_chain_json(n + 3 + longer), n + 3 + longer),
    }
}

/// Parallelises `sequence` of `source` from `config` (lattice forms, blocks allowed).
fn run(source: &str, sequence: &str, config: &str) -> Parallelised {
    with_request(source, sequence, config, |request| {
        parallelise(request).unwrap_or_else(|e| panic!("{e:?}"))
    })
}

/// Builds the request of `run` and hands it to `f`.
fn with_request<T>(source: &str, sequence: &str, config: &str, f: impl Fn(&Request) -> T) -> T {
    with_request_for(true, source, sequence, config, f)
}

/// `with_request`, with one module's independent statements joined (`overlap`, the lattice
/// protocol) or kept in order (the paper's protocol).
fn with_request_for<T>(
    overlap: bool,
    source: &str,
    sequence: &str,
    config: &str,
    f: impl Fn(&Request) -> T,
) -> T {
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let plan = program.expand(sequence).expect("sequence");
    let assignment = assign_modules(&program, &[plan], &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let request = Request {
        program: &program,
        sequence,
        world,
        assignment: &assignment,
        name: "out",
        blocks: true,
        one_module_overlap: overlap,
        window: None,
    };
    f(&request)
}

/// Replays `out` of `header + text` and its reverse, and checks independence on both: the
/// final configuration of the forward run.
fn check_written(found: &Parallelised, text: &str, config: &str) -> Configuration {
    let source = format!("{}\n{text}\nsequence back = reverse out;\n", found.header);
    let parsed = parse(&source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{source}\n{diagnostics:?}"));
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let forward = vec![program.expand("out").expect("out")];
    let assignment = assign_modules(&program, &forward, &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let done = replay(&program, &forward, world.clone(), &assignment);
    assert_eq!(done.n_rejected, 0, "{source}\n{:?}", done.diagnostics);
    let warnings = check_independence(&program, &forward, world, &assignment);
    assert!(warnings.is_empty(), "{source}\n{warnings:?}");
    let back = vec![program.expand("back").expect("back")];
    let end = done.final_world.clone();
    let undone = replay(&program, &back, end.clone(), &assignment);
    assert_eq!(undone.n_rejected, 0, "{source}\n{:?}", undone.diagnostics);
    let warnings = check_independence(&program, &back, end, &assignment);
    assert!(warnings.is_empty(), "reverse of\n{source}\n{warnings:?}");
    done.final_world
        .configuration()
        .expect("a file-format robot")
}

/// The final configuration of `sequence` replayed as written.
fn replayed(source: &str, sequence: &str, config: &str) -> Configuration {
    let parsed = parse(source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("program");
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let plans = vec![program.expand(sequence).expect("sequence")];
    let assignment = assign_modules(&program, &plans, &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    replay(&program, &plans, world, &assignment)
        .final_world
        .configuration()
        .expect("a file-format robot")
}

/// The group (top-level element) each statement is in.
fn group_of(layout: &Layout, statement: usize) -> Option<usize> {
    let Layout::Seq(groups) = layout else {
        return contains(layout, statement).then_some(0);
    };
    groups.iter().position(|g| contains(g, statement))
}

fn contains(layout: &Layout, statement: usize) -> bool {
    match layout {
        Layout::Op(s) => *s == statement,
        Layout::Seq(v) | Layout::Par(v) => v.iter().any(|l| contains(l, statement)),
    }
}

fn sequential(source: &str) -> String {
    source.replace(" &\n", ";\n")
}

#[test]
fn eight2car_written_in_order_comes_back_parallel_and_safe() {
    let source = sequential(EIGHT2CAR);
    assert!(!source.contains(" &"));
    let found = run(&source, "eight2car", EIGHT);
    assert_eq!(found.statements.len(), 25);
    let expected = replayed(EIGHT2CAR, "eight2car", EIGHT);
    for form in &found.forms {
        let end = check_written(&found, &form.text, EIGHT);
        assert_eq!(compare(&end, &expected), Ok(()));
    }
    assert_eq!(found.forms[0].kind, FormKind::Levels);
    // The shipped, hand-parallel file has 16 groups.
    assert!(found.forms[0].groups <= 16, "{}", found.forms[0].text);
}

#[test]
fn the_order_dependent_turns_of_fig5_stay_in_order() {
    // Fig. 5 joins M0's and M1's turns (statements 11 and 12); they sweep through each other
    // in one order, so every form keeps them in different groups, M0's first.
    let found = run(FIG5, "eight2car", EIGHT);
    assert!(found.statements[11].starts_with("M0.Joint.rotateFromToBy(0, 324"));
    assert!(found.statements[12].starts_with("M1.Joint.rotateFromToBy(324, 0"));
    for form in &found.forms {
        let (a, b) = (group_of(&form.layout, 11), group_of(&form.layout, 12));
        assert!(a.is_some() && a < b, "{}", form.text);
        check_written(&found, &form.text, EIGHT);
    }
}

#[test]
fn a_chain_of_dependent_statements_stays_a_chain() {
    // One module's connector, released and made again: nothing can move.
    let source = "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    \
                  M0.Connector[0].extend();\n    M0.Connector[0].retract();\n}\n";
    let found = run(source, "s", EIGHT);
    assert_eq!(found.edges, vec![(0, 1), (1, 2)]);
    assert_eq!(found.forms.len(), 1);
    assert_eq!(found.forms[0].groups, 3);
}

#[test]
fn transitive_reduction_keeps_only_the_needed_edges() {
    let edges = [(0, 1), (1, 2), (0, 2), (2, 3), (0, 3), (1, 4)];
    assert_eq!(
        dynarole_replay::transitive_reduction(5, &edges),
        vec![(0, 1), (1, 2), (1, 4), (2, 3)]
    );
}

/// A straight M-TRAN snake of `n` modules.
fn mtran_snake(n: usize) -> String {
    let modules: Vec<String> = (0..n)
        .map(|k| {
            format!(
                r#"{{"name": "T{k}", "id": {k}, "position": [{}, 0, 0], "orientation": "ORI2", "joints_deg": [0, 0]}}"#,
                2 * k
            )
        })
        .collect();
    let connections: Vec<String> = (0..n - 1)
        .map(|k| format!(r#"["T{}", 0, "T{k}", 3]"#, k + 1))
        .collect();
    format!(
        r#"{{"name": "snake", "robot": "MTRAN", "modules": [{}], "connections": [{}]}}"#,
        modules.join(", "),
        connections.join(", ")
    )
}

/// Random operations tried on the ATRON model; the accepted ones (without warnings), as
/// statements. A pick is (module, operation, connector or direction).
fn atron_moves(config: &str, n: usize, picks: &[(usize, u8, u8)]) -> Vec<String> {
    let c = (dynarole_robots::read_configuration(config))
        .ok()
        .and_then(|c| {
            c.downcast_ref::<dynarole_robot_atron::AtronConfiguration>()
                .cloned()
        })
        .expect("atron configuration");
    let mut world = World::new(c);
    let mut out = Vec::new();
    for &(m, op, arg) in picks {
        let (m, name) = (m % n, format!("M{}", m % n));
        let joint = world.configuration().modules()[m].joint_units;
        let c = arg % 8;
        let mut trial = world.clone();
        let (text, ok) = match op % 3 {
            0 => (
                format!("M{m}.Connector[{c}].retract()"),
                trial.retract(&name, c),
            ),
            1 => (
                format!("M{m}.Connector[{c}].extend()"),
                trial.extend(&name, c),
            ),
            _ => {
                let up = arg % 2 == 0;
                let to = if up {
                    (joint + 108) % 432
                } else {
                    (joint + 324) % 432
                };
                (
                    format!("M{m}.Joint.rotateFromToBy({joint}, {to}, {up}, 150)"),
                    trial.rotate(&name, joint, to, up),
                )
            }
        };
        // A step with a warning is done by the model but not kept: the world goes back.
        if ok.is_ok_and(|o| o.warnings.is_empty()) {
            world = trial;
            out.push(text);
        }
    }
    out
}

/// The same for the M-TRAN model (joints turn between -90, 0 and 90 degrees).
fn mtran_moves(config: &str, n: usize, picks: &[(usize, u8, u8)]) -> Vec<String> {
    let c = (dynarole_robots::read_configuration(config))
        .ok()
        .and_then(|c| {
            c.downcast_ref::<dynarole_robot_mtran::MtranConfiguration>()
                .cloned()
        })
        .expect("mtran configuration");
    let mut world = MtranWorld::new(c);
    let mut out = Vec::new();
    for &(m, op, arg) in picks {
        let (m, name) = (m % n, format!("T{}", m % n));
        let c = arg % 6;
        let mut trial = world.clone();
        let (text, ok) = match op % 3 {
            0 => (
                format!("M{m}.Connector[{c}].retract()"),
                trial.disconnect(&name, c),
            ),
            1 => (
                format!("M{m}.Connector[{c}].extend()"),
                trial.connect(&name, c),
            ),
            _ => {
                let (joint, index) = if arg % 2 == 0 {
                    (MtranJoint::North, 0)
                } else {
                    (MtranJoint::South, 1)
                };
                let from = world.configuration().modules()[m].joints_deg[index];
                let to = match (from, arg % 4 < 2) {
                    (0, true) => 90,
                    (0, false) => -90,
                    _ => 0,
                };
                let up = to > from;
                (
                    format!("M{m}.Joint[{index}].rotateFromToBy({from}, {to}, {up}, 100)"),
                    trial.rotate(&name, joint, from, to, up),
                )
            }
        };
        // A step with a warning is done by the model but not kept: the world goes back.
        if ok.is_ok_and(|o| o.warnings.is_empty()) {
            world = trial;
            out.push(text);
        }
    }
    out
}

fn source_of(robot: &str, moves: &[String]) -> String {
    let body: String = moves.iter().map(|m| format!("    {m};\n")).collect();
    format!("robot {robot};\nsequence s {{\n{body}}}\n")
}

fn random_case(robot: &str, config: &str, moves: &[String]) -> Result<(), TestCaseError> {
    let source = source_of(robot, moves);
    let found = run(&source, "s", config);
    let expected = replayed(&source, "s", config);
    // The builder's groups are checked as wholes: the verification has nothing to repair.
    let repairs: Vec<&String> = found
        .notes
        .iter()
        .filter(|n| n.contains("` before `"))
        .collect();
    prop_assert!(repairs.is_empty(), "{}\n{:?}", source, repairs);
    for form in &found.forms {
        let end = check_written(&found, &form.text, config);
        prop_assert_eq!(
            compare(&end, &expected),
            Ok(()),
            "{}\n{}",
            source,
            form.text
        );
    }
    Ok(())
}

/// The fast dependency graph is the exhaustive one (every pair run both ways).
fn same_graph(robot: &str, config: &str, moves: &[String]) -> Result<(), TestCaseError> {
    let source = source_of(robot, moves);
    let (fast, exhaustive) = with_request(&source, "s", config, |request| {
        (
            dependency_graph(request, false).unwrap_or_else(|e| panic!("{e:?}")),
            dependency_graph(request, true).unwrap_or_else(|e| panic!("{e:?}")),
        )
    });
    prop_assert_eq!(fast, exhaustive, "{}", source);
    Ok(())
}

/// The independence check of `moves` joined by `&` where `joins` says so (else `;`), with
/// turns decided from their motions, warns exactly like the one running every pair both ways.
fn same_warnings(
    robot: &str,
    config: &str,
    moves: &[String],
    joins: &[bool],
) -> Result<(), TestCaseError> {
    let mut body = String::new();
    for (k, m) in moves.iter().enumerate() {
        let join = joins.get(k).copied().unwrap_or(false) && k + 1 < moves.len();
        body.push_str(&format!("    {m}{}\n", if join { " &" } else { ";" }));
    }
    let source = format!("robot {robot};\nsequence s {{\n{body}}}\n");
    let parsed = parse(&source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{source}\n{diagnostics:?}"));
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let plans = vec![program.expand("s").expect("s")];
    let assignment = assign_modules(&program, &plans, &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let fast = check_independence(&program, &plans, world.clone(), &assignment);
    let exhaustive = check_independence_exhaustive(&program, &plans, world, &assignment);
    prop_assert_eq!(format!("{fast:?}"), format!("{exhaustive:?}"), "{}", source);
    Ok(())
}

#[test]
fn a_turn_whose_sweep_is_blocked_before_an_earlier_turn_stays_after_it() {
    // On the car, M1's turn (statement 3) is accepted where the input runs it but refused (its
    // sweep) on the state before M5's turn (statement 1), although the two turns move disjoint
    // sides that stay apart: only that sweep orders them. Found by the property test.
    let moves: Vec<String> = [
        "M6.Joint.rotateFromToBy(108, 216, true, 150)",
        "M5.Joint.rotateFromToBy(0, 108, true, 150)",
        "M6.Joint.rotateFromToBy(216, 324, true, 150)",
        "M1.Joint.rotateFromToBy(216, 324, true, 150)",
    ]
    .map(String::from)
    .to_vec();
    same_graph("atron", CAR, &moves).expect("the same graph");
    let source = source_of("atron", &moves);
    let edges = with_request(&source, "s", CAR, |request| {
        dependency_graph(request, false).expect("graph")
    });
    assert!(edges.contains(&(1, 3)), "{edges:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn random_atron_sequences_replay_to_the_same_end(
        structure in 0usize..8,
        picks in proptest::collection::vec((0usize..8, 0u8..3, 0u8..8), 1..40),
    ) {
        let (config, n) = atron_structure(structure, 0);
        let moves = atron_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        random_case("atron", &config, &moves)?;
    }

    #[test]
    fn random_mtran_sequences_replay_to_the_same_end(
        n in 2usize..6,
        picks in proptest::collection::vec((0usize..6, 0u8..3, 0u8..8), 1..24),
    ) {
        let config = mtran_snake(n);
        let moves = mtran_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        random_case("mtran", &config, &moves)?;
    }

    #[test]
    fn the_fast_graph_is_the_exhaustive_one_on_atron(
        structure in 0usize..8,
        longer in 0usize..16,
        picks in proptest::collection::vec((0usize..24, 0u8..3, 0u8..8), 1..80),
    ) {
        // Chains of up to 22 modules: turns at the two ends move disjoint sides.
        let (config, n) = atron_structure(structure, longer);
        let moves = atron_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        same_graph("atron", &config, &moves)?;
    }

    #[test]
    fn the_fast_independence_check_is_the_exhaustive_one_on_atron(
        structure in 0usize..8,
        longer in 0usize..16,
        picks in proptest::collection::vec((0usize..24, 0u8..3, 0u8..8), 1..60),
        joins in proptest::collection::vec(proptest::bool::weighted(0.7), 60),
    ) {
        // Valid in order, joined into random groups: some groups are independent, some not.
        let (config, n) = atron_structure(structure, longer);
        let moves = atron_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        same_warnings("atron", &config, &moves, &joins)?;
    }

    #[test]
    fn the_fast_graph_is_the_exhaustive_one_on_few_modules_of_atron(
        structure in 0usize..8,
        picks in proptest::collection::vec((0usize..2, 0u8..3, 0u8..8), 1..40),
        base in 0usize..7,
    ) {
        // Moves of two neighbouring modules only: most pairs are one module's statements,
        // decided by the model like any other pair.
        let (config, n) = atron_structure(structure, 0);
        let picks: Vec<(usize, u8, u8)> =
            picks.iter().map(|&(m, op, arg)| ((base + m) % n, op, arg)).collect();
        let moves = atron_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        same_graph("atron", &config, &moves)?;
        random_case("atron", &config, &moves)?;
    }

    #[test]
    fn the_fast_graph_is_the_exhaustive_one_on_mtran(
        n in 2usize..6,
        picks in proptest::collection::vec((0usize..6, 0u8..3, 0u8..8), 1..40),
    ) {
        let config = mtran_snake(n);
        let moves = mtran_moves(&config, n, &picks);
        prop_assume!(!moves.is_empty());
        same_graph("mtran", &config, &moves)?;
    }
}

#[test]
fn one_modules_independent_statements_are_joined() {
    // eight2snake releases two of M3's latches: both orders end the same and neither is
    // refused, so the lattice forms join them with `&` (the runtime starts them as one
    // batch), as the shipped file does.
    let source = sequential(EIGHT2CAR);
    let found = run(&source, "eight2snake", EIGHT);
    assert!(found.statements[0].starts_with("M3.Connector[$CONNECTOR_0].retract"));
    assert!(found.statements[1].starts_with("M3.Connector[$CONNECTOR_6].retract"));
    assert!(!found.edges.contains(&(0, 1)), "{:?}", found.edges);
    assert!(
        !found
            .notes
            .iter()
            .any(|n| n.contains("one module does both")),
        "{:?}",
        found.notes
    );
    // Every form is written from that graph (there is no other candidate graph).
    for form in &found.forms {
        assert_eq!(
            group_of(&form.layout, 0),
            group_of(&form.layout, 1),
            "{}",
            form.text
        );
    }
    for form in &found.forms {
        check_written(&found, &form.text, EIGHT);
    }
}

/// Where each statement runs in the levels form of `edges`: its group (one after its latest
/// parent's), then its place in the group (input order, as written and replayed).
fn positions(n: usize, edges: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let mut level = vec![0; n];
    let mut sorted = edges.to_vec();
    sorted.sort_unstable_by_key(|&(_, j)| j);
    for (i, j) in sorted {
        level[j] = level[j].max(level[i] + 1);
    }
    level.into_iter().zip(0..n).collect()
}

#[test]
fn three_statements_that_split_the_robot_only_together_are_kept_apart_by_the_builder() {
    // eight2car: M3's two retracts and M1's extend are independent two by two, but with both
    // retracts done before the extend M3 is alone. The pair graph's groups do that; the graph
    // the builder writes (each group checked as a whole from the state it starts from) keeps
    // one of the retracts after the extend and never the three in one group, before any
    // verification or other candidate.
    let source = sequential(EIGHT2CAR);
    let found = run(&source, "eight2car", EIGHT);
    let at = |text: &str| {
        let index = found.statements.iter().position(|s| s == text);
        index.unwrap_or_else(|| panic!("{text} in {:?}", found.statements))
    };
    let extend = at("M1.Connector[$CONNECTOR_6].extend()");
    let retracts = [
        at("M3.Connector[$CONNECTOR_0].retract()"),
        at("M3.Connector[$CONNECTOR_2].retract()"),
    ];
    let n = found.statements.len();
    let (pairs, grouped) = with_request(&source, "eight2car", EIGHT, |request| {
        (
            dependency_graph(request, false).unwrap_or_else(|e| panic!("{e:?}")),
            group_checked_graph(request).unwrap_or_else(|e| panic!("{e:?}")),
        )
    });
    let m3_alone = |edges: &[(usize, usize)]| {
        let at = positions(n, edges);
        retracts.iter().all(|&r| at[r] < at[extend])
    };
    let one_group = |edges: &[(usize, usize)]| {
        let at = positions(n, edges);
        retracts.iter().all(|&r| at[r].0 == at[extend].0)
    };
    assert!(m3_alone(&pairs), "the pair graph: {pairs:?}");
    assert!(!m3_alone(&grouped), "the builder's groups: {grouped:?}");
    assert!(!one_group(&grouped), "the builder's groups: {grouped:?}");
    // What is printed is the builder's own levels: the verification repaired nothing.
    assert!(
        !found.notes.iter().any(|n| n.contains("` before `")),
        "{:?}",
        found.notes
    );
    assert_eq!(found.forms[0].kind, FormKind::Levels);
    assert_eq!(found.edges, grouped);
}

#[test]
fn one_modules_dependent_statements_stay_in_order() {
    // One module's turn, then a latch of the same module that the turn brings face to face
    // (or releases): the model needs the order, whoever does the two statements.
    let source = "robot atron;\nsequence s {\n    M0.Connector[0].retract();\n    \
                  M0.Connector[0].extend();\n}\n";
    let found = run(source, "s", EIGHT);
    assert_eq!(found.edges, vec![(0, 1)]);
}

#[test]
fn for_the_paper_protocol_one_modules_statements_stay_in_order_and_the_notes_say_why() {
    // The paper's protocol runs one module's statements one after the other in a group with
    // other modules' statements: `&` would gain nothing there.
    let source = sequential(EIGHT2CAR);
    let found = with_request_for(false, &source, "eight2snake", EIGHT, |request| {
        parallelise(request).unwrap_or_else(|e| panic!("{e:?}"))
    });
    assert!(found.edges.contains(&(0, 1)), "{:?}", found.edges);
    assert!(
        found
            .notes
            .iter()
            .any(|n| n.contains("one module does both")),
        "{:?}",
        found.notes
    );
}

#[test]
fn a_turn_moved_by_an_earlier_one_is_looked_at_again() {
    // On the snake, M2's turn back (statement 3) moves M1, which M0's turn (statement 5)
    // moves: M0's moving side found on the state after M2's turn is not the one before it.
    // Found by the property test.
    let moves: Vec<String> = [
        "M2.Joint.rotateFromToBy(0, 108, true, 150)",
        "M3.Joint.rotateFromToBy(0, 108, true, 150)",
        "M4.Joint.rotateFromToBy(0, 108, true, 150)",
        "M2.Joint.rotateFromToBy(108, 0, false, 150)",
        "M4.Joint.rotateFromToBy(108, 216, true, 150)",
        "M0.Joint.rotateFromToBy(216, 324, true, 150)",
    ]
    .map(String::from)
    .to_vec();
    same_graph("atron", SNAKE, &moves).expect("the same graph");
}

/// eight2car written in order, but with M3's connector 0 released before M1's connector 6
/// latches to M3, and then `first` and `second` (that extend and the retract of M3's connector
/// 2, the one latch left holding M3) joined by `&`, or by `;` when `joined` is false.
fn extend_and_retract(first: &str, second: &str, joined: bool) -> String {
    let three = "    M1.Connector[$CONNECTOR_6].extend();\n    \
                 M3.Connector[$CONNECTOR_0].retract();\n    \
                 M3.Connector[$CONNECTOR_2].retract();\n";
    let source = sequential(EIGHT2CAR);
    assert!(source.contains(three), "{source}");
    let separator = if joined { " &" } else { ";" };
    let now = format!(
        "    M3.Connector[$CONNECTOR_0].retract();\n    {first}{separator}\n    {second};\n"
    );
    source.replace(three, &now)
}

const EXTEND: &str = "M1.Connector[$CONNECTOR_6].extend()";
const RETRACT: &str = "M3.Connector[$CONNECTOR_2].retract()";

#[test]
fn an_extend_and_a_retract_it_makes_safe_are_not_independent() {
    // Once M3's connector 0 is released, only M3.Connector[2] holds M3 to the rest until M1's
    // connector 6 latches to it: both orders are accepted and end alike, but if the retract
    // ends first the robot is in two parts for a moment. Either way round.
    for (first, second) in [(EXTEND, RETRACT), (RETRACT, EXTEND)] {
        let source = extend_and_retract(first, second, true);
        let parsed = parse(&source);
        let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
        let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
        let config = dynarole_robots::read_configuration(EIGHT).expect("configuration");
        let plans = vec![program.expand("eight2car").expect("sequence")];
        let assignment = assign_modules(&program, &plans, &config).expect("labels");
        let world = RobotWorld::new(config, &program.robot).expect("world");
        let done = replay(&program, &plans, world.clone(), &assignment);
        assert_eq!(done.n_rejected, 0, "{:?}", done.diagnostics);
        for warnings in [
            check_independence(&program, &plans, world.clone(), &assignment),
            check_independence_exhaustive(&program, &plans, world.clone(), &assignment),
        ] {
            let reasons: Vec<String> = warnings.iter().map(|w| format!("{:?}", w.kind)).collect();
            assert_eq!(reasons.len(), 1, "{reasons:?}");
            assert!(
                reasons[0].contains(
                    "if `M3.Connector[2].retract()` ends first: the robot is now in two parts: \
                     [M3] and [M0, M1, M2, M4, M5, M6]"
                ),
                "{reasons:?}"
            );
        }
    }
}

#[test]
fn parallelise_keeps_a_retract_after_the_extend_that_makes_it_safe() {
    // The pair graph itself (not only the group check) orders the two statements the test
    // above joins: a warning in one order only is an edge, as for `check --from`.
    let source = extend_and_retract(EXTEND, RETRACT, false);
    let found = run(&source, "eight2car", EIGHT);
    let at = |text: &str| {
        let index = found.statements.iter().position(|s| s == text);
        index.unwrap_or_else(|| panic!("{text} in {:?}", found.statements))
    };
    let (extend, retract) = (at(EXTEND), at(RETRACT));
    let pairs = with_request(&source, "eight2car", EIGHT, |request| {
        dependency_graph(request, false).unwrap_or_else(|e| panic!("{e:?}"))
    });
    let n = found.statements.len();
    assert!(pairs.contains(&(extend, retract)), "{pairs:?}");
    assert!(positions(n, &found.edges)[retract].0 > positions(n, &found.edges)[extend].0);
    check_written(&found, &found.forms[0].text, EIGHT);
}
