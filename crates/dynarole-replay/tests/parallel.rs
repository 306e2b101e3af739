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
    // The builder's groups are checked as wholes, but its edges pair by pair on the input's
    // states: moving two later statements before an earlier one can change the state it runs
    // on though each alone does not (a snake case: a turn refused after two others that each
    // commute with it). The verification then repairs the form, and never gives up on a
    // parallel form for want of an edge to add; what it writes must end where the input does.
    let fell_back = found
        .notes
        .iter()
        .any(|n| n.contains("written in the input order"));
    prop_assert!(!fell_back, "{}\n{:?}", source, found.notes);
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

/// A warning as text, a split the same whichever side commanded it (as the check compares).
fn warning_text(warning: &dynarole_world::Warning) -> String {
    match warning {
        dynarole_world::Warning::Split { first, second } => {
            let mut sides = [first.join(","), second.join(",")];
            sides.sort();
            format!("split {sides:?}")
        }
        other => format!("{other:?}"),
    }
}

/// Every order of `items`, by swapping (k! of them).
fn orders_of(items: &[usize]) -> Vec<Vec<usize>> {
    if items.len() <= 1 {
        return vec![items.to_vec()];
    }
    let mut out = Vec::new();
    for (i, &first) in items.iter().enumerate() {
        let rest: Vec<usize> = (items.iter().enumerate())
            .filter(|&(k, _)| k != i)
            .map(|(_, &x)| x)
            .collect();
        for mut order in orders_of(&rest) {
            order.insert(0, first);
            out.push(order);
        }
    }
    out
}

/// Does some completion order of `moves[group]`, run one after the other from the state the
/// moves before it leave, give another end, another warning or a refusal than the written
/// order? Every order is run (the reference the subset check is tested against); `None` when
/// the written order itself is refused.
fn some_order_differs(
    config: &str,
    moves: &[String],
    group: std::ops::Range<usize>,
) -> Option<bool> {
    let source = source_of("atron", moves);
    let parsed = parse(&source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("program");
    let plan = program.expand("s").expect("s");
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let assignment =
        assign_modules(&program, std::slice::from_ref(&plan), &config).expect("labels");
    let statements = plan.statements();
    let run = |world: &mut RobotWorld, i: usize| {
        let module = &assignment[&statements[i].label];
        world.apply(&program.robot, statements[i], module)
    };
    let mut start = RobotWorld::new(config, &program.robot).expect("world");
    for i in 0..group.start {
        run(&mut start, i).expect("the moves are valid in order");
    }
    let outcome = |order: &[usize]| {
        let mut world = start.clone();
        let mut warnings = Vec::new();
        for &i in order {
            let outcome = run(&mut world, i).ok()?;
            warnings.extend(outcome.warnings.iter().map(warning_text));
        }
        warnings.sort();
        Some((world, warnings))
    };
    let written: Vec<usize> = group.clone().collect();
    let (end, warnings) = outcome(&written)?;
    Some(
        orders_of(&written)
            .iter()
            .any(|order| match outcome(order) {
                None => true,
                Some((other_end, other_warnings)) => {
                    other_end.difference(&end).is_some() || other_warnings != warnings
                }
            }),
    )
}

/// The connector operations the model accepts without a warning on `config` (of `n`
/// modules), as statements.
fn atron_connector_operations(config: &str, n: usize) -> Vec<String> {
    let picks: Vec<(usize, u8, u8)> = (0..n)
        .flat_map(|m| (0..2u8).flat_map(move |op| (0..8u8).map(move |c| (m, op, c))))
        .collect();
    // Each pick alone, from the start: `atron_moves` keeps it when it is accepted.
    picks
        .iter()
        .flat_map(|&pick| atron_moves(config, n, &[pick]))
        .collect()
}

/// `moves` with `moves[group]` joined by `&`, checked from `config`: its warnings.
fn group_warnings(config: &str, moves: &[String], group: std::ops::Range<usize>) -> Vec<String> {
    let mut body = String::new();
    for (k, m) in moves.iter().enumerate() {
        let join = group.contains(&k) && k + 1 < group.end;
        body.push_str(&format!("    {m}{}\n", if join { " &" } else { ";" }));
    }
    let source = format!("robot atron;\nsequence s {{\n{body}}}\n");
    let parsed = parse(&source);
    let (program, _) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.expect("program");
    let config = dynarole_robots::read_configuration(config).expect("configuration");
    let plans = vec![program.expand("s").expect("s")];
    let assignment = assign_modules(&program, &plans, &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let warnings = check_independence(&program, &plans, world, &assignment);
    warnings.iter().map(|d| format!("{:?}", d.kind)).collect()
}

#[test]
fn three_statements_that_split_the_robot_only_together_are_warned_by_the_check() {
    // The group `parallelise` never writes, written by hand: each pair is fine, both retracts
    // before the extend leave M3 alone.
    let source = sequential(EIGHT2CAR);
    let moves: Vec<String> = (source.lines())
        .filter(|l| l.trim_end().ends_with(';') && l.contains('.'))
        .map(|l| l.trim().trim_end_matches(';').to_string())
        .collect();
    let at = |text: &str| moves.iter().position(|m| m == text);
    let extend = at("M1.Connector[$CONNECTOR_6].extend()").expect("the extend");
    let group = extend..extend + 3;
    assert!(
        moves[group.end - 1].contains("retract"),
        "{:?}",
        &moves[group.clone()]
    );
    assert_eq!(some_order_differs(EIGHT, &moves, group.clone()), Some(true));
    let warnings = group_warnings(EIGHT, &moves, group);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("the robot is now in two parts"),
        "{warnings:?}"
    );
}

/// A group of `len` moves from `first` (wrapped to fit), when there are enough moves.
fn group_in(moves: &[String], first: usize, len: usize) -> Option<std::ops::Range<usize>> {
    let start = first % (moves.len().checked_sub(len)? + 1);
    Some(start..start + len)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn a_group_of_connector_operations_is_warned_exactly_when_some_order_differs(
        structure in 5usize..8,
        picks in proptest::collection::vec(0usize..64, 3..6),
    ) {
        // Latches move nothing: whether such a group is independent is all in its completion
        // orders, here run one by one (up to 120 of them) against the check's subsets. The
        // group: distinct operations each valid alone on one of the paper's shapes (which
        // have loops), in a random order.
        let (config, n) = atron_structure(structure, 0);
        let candidates = atron_connector_operations(&config, n);
        prop_assume!(!candidates.is_empty());
        let mut moves: Vec<String> = Vec::new();
        for pick in picks {
            let operation = &candidates[pick % candidates.len()];
            if !moves.contains(operation) {
                moves.push(operation.clone());
            }
        }
        prop_assume!(moves.len() >= 3);
        let differs = some_order_differs(&config, &moves, 0..moves.len());
        prop_assume!(differs.is_some());
        let warnings = group_warnings(&config, &moves, 0..moves.len());
        prop_assert_eq!(differs, Some(!warnings.is_empty()), "{:?}\n{:?}", moves, warnings);
    }

    #[test]
    fn a_group_some_order_of_which_differs_is_warned(
        structure in 0usize..8,
        picks in proptest::collection::vec((0usize..7, 0u8..3, 0u8..8), 20..120),
        first in 0usize..64,
        len in 3usize..6,
    ) {
        // With turns, the check also warns where the motions overlap: one way only.
        let (config, n) = atron_structure(structure, 0);
        let moves = atron_moves(&config, n, &picks);
        let group = group_in(&moves, first, len);
        prop_assume!(group.is_some());
        let group = group.unwrap_or_default();
        if some_order_differs(&config, &moves, group.clone()) == Some(true) {
            let warnings = group_warnings(&config, &moves, group);
            prop_assert!(!warnings.is_empty(), "{:?}", moves);
        }
    }
}

/// Eight2car's configuration just before M1's extend that holds M3 (statement `before` of the
/// sequence written in order), replayed.
fn eight2car_before(before: &str) -> Configuration {
    let source = sequential(EIGHT2CAR);
    let cut = source.find(before).expect("the statement");
    let prefix = format!("{}}}\n", &source[..cut]);
    replayed(&prefix, "eight2car", EIGHT)
}

#[test]
fn a_group_that_splits_the_robot_only_in_another_order_than_the_input_is_split_by_the_builder() {
    // Where M3 is held by its connectors 0 and 2 only: extending M1's 6 (which holds M3 too),
    // then retracting 0 and 2 is fine, and so is each pair, but both retracts before the
    // extend leave M3 alone. Only the completion orders show it (the input's own order and
    // its pairs do not): the builder keeps the second retract out of the group, and the
    // verification repairs nothing.
    let config = eight2car_before("    M1.Connector[$CONNECTOR_6].extend();");
    let source = "robot atron;\nsequence s {\n    M1.Connector[$CONNECTOR_6].extend();\n    \
                  M3.Connector[$CONNECTOR_0].retract();\n    M3.Connector[$CONNECTOR_2].retract();\n}\n";
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &dynarole_robots::plugins());
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let plan = program.expand("s").expect("s");
    let assignment = assign_modules(&program, &[plan], &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let request = Request {
        program: &program,
        sequence: "s",
        world,
        assignment: &assignment,
        name: "out",
        blocks: true,
        one_module_overlap: true,
        window: None,
    };
    let found = parallelise(&request).unwrap_or_else(|e| panic!("{e:?}"));
    let repairs: Vec<&String> = (found.notes.iter())
        .filter(|n| n.contains("` before `"))
        .collect();
    assert!(
        repairs.is_empty(),
        "{:?}\n{}",
        found.notes,
        found.forms[0].text
    );
    let grouped = group_checked_graph(&request).unwrap_or_else(|e| panic!("{e:?}"));
    let at = positions(3, &grouped);
    assert!(
        at[2].0 > at[0].0,
        "the second retract after the first: {grouped:?}"
    );
    assert!(
        found.notes.iter().any(|n| n.contains("if they end")),
        "the reason is given: {:?}\n{}\n{grouped:?}",
        found.notes,
        found.forms[0].text
    );
}
