//! A robot defined only here (`fixtures/hinged_cubes/`: its plugin and its model of a chain
//! of hinged cubes) goes through the whole tool without any change to the tool's crates: the
//! checker with its plugin, the replay and independence check on its model, and the simulator
//! running the generated C on every cube, each reaching the expected ring.

#[path = "fixtures/hinged_cubes/mod.rs"]
mod hinged_cubes;

use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{driver, parse, Program, RobotApi};
use dynarole_replay::{assign_modules_on, check_independence, replay, RobotWorld};
use dynarole_sim::{ModelRun, Scenario, Simulator};
use dynarole_world::RobotModel;
use hinged_cubes::{Cubes, PLUGIN, RING};

fn plugin() -> RobotApi {
    RobotApi::from_toml(PLUGIN).expect("the fixture's plugin loads")
}

/// `source` checked by the program driver, with the plugin found beside it.
fn check(parsed: &dynarole_core::Parsed) -> Program<'_> {
    let registry = driver::registry(
        dynarole_robots::plugins(),
        driver::robot_name(&parsed.file),
        [],
        |file| {
            assert_eq!(file, "cubes.robot.toml");
            Ok::<_, ()>(Some(plugin()))
        },
    )
    .expect("registry");
    driver::check(parsed, &registry).unwrap_or_else(|d| panic!("{d:?}"))
}

/// `sequence` replayed on `start`; the end, and every diagnostic of the replay and of the
/// independence check.
fn replayed(program: &Program, sequence: &str, start: Cubes) -> (RobotWorld, Vec<String>) {
    let plans = driver::plans(program, &[sequence.to_string()]).expect("sequence");
    let world = RobotWorld::from_model(Box::new(start), &program.robot).expect("a cubes model");
    let assignment = assign_modules_on(program, &plans, world.view()).expect("labels");
    let done = replay(program, &plans, world.clone(), &assignment);
    let mut problems: Vec<String> = done
        .diagnostics
        .iter()
        .map(|d| format!("{:?}", d.kind))
        .collect();
    let independence = check_independence(program, &plans, world, &assignment);
    problems.extend(independence.iter().map(|d| format!("{:?}", d.kind)));
    (done.final_world, problems)
}

#[test]
fn the_plugin_declares_what_each_operation_does() {
    use dynarole_core::robot::OperationKind;
    let api = plugin();
    let kinds: Vec<OperationKind> = api
        .parts
        .iter()
        .flat_map(|p| p.operations.iter().map(|o| o.kind))
        .collect();
    assert_eq!(
        kinds,
        [
            OperationKind::Extend,
            OperationKind::Retract,
            OperationKind::Turn
        ]
    );
}

#[test]
fn the_ring_replays_on_the_model_and_reverses() {
    let parsed = parse(RING);
    let program = check(&parsed);
    let (end, problems) = replayed(&program, "ring", Cubes::line(4));
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(end.model().difference(&Cubes::ring()), None);
    assert_eq!(
        end.view()
            .latched_to(dynarole_world::Port {
                module: 3,
                connector: 0
            })
            .map(|p| p.module),
        Some(0)
    );
    let (back, problems) = replayed(&program, "open", Cubes::ring());
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(back.model().difference(&Cubes::line(4)), None);
}

#[test]
fn the_model_refuses_what_the_cubes_cannot_do() {
    let source = RING.replace(
        "    M0.Hinge.bend(0, 90, true, 100);\n",
        "    M3.Connector[$FRONT].latch();\n",
    );
    let parsed = parse(&source);
    let program = check(&parsed);
    let (end, problems) = replayed(&program, "ring", Cubes::line(4));
    assert!(
        problems.iter().any(|p| p.contains("nothing to latch onto")),
        "latching before the ring is closed: {problems:?}"
    );
    assert!(end.model().difference(&Cubes::ring()).is_some());
    let locked = RING.replace(
        "sequence open = reverse ring;",
        "sequence more {\n    M0.Hinge.bend(90, 0, false, 100);\n}",
    );
    let parsed = parse(&locked);
    let program = check(&parsed);
    let (_, problems) = replayed(&program, "more", Cubes::ring());
    assert!(problems.iter().any(|p| p.contains("loop")), "{problems:?}");
}

#[test]
fn a_model_of_another_robot_is_refused() {
    let atron = dynarole_robots::plugins()
        .get("atron")
        .cloned()
        .expect("built in");
    let refused = RobotWorld::from_model(Box::new(Cubes::line(2)), &atron).expect_err("not atron");
    assert!(refused.contains("robot `cubes`"), "{refused}");
}

#[test]
fn the_generated_c_folds_the_ring_on_every_cube() {
    let parsed = parse(RING);
    let program = check(&parsed);
    let plans = driver::plans(&program, &["ring".to_string()]).expect("ring");
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "cubes".into(),
        ..CompileOptions::default()
    };
    let sim = Simulator::new(&program, &plans, &options).expect("compiles");
    let (start, ring) = (Cubes::line(4), Cubes::ring());
    let scenario = Scenario::default();
    for seed in [1, 2] {
        let report = sim
            .run_model(&ModelRun {
                start: &start,
                expect: Some(&ring as &dyn RobotModel),
                scenario: &scenario,
                seed,
                trace: false,
            })
            .expect("runs");
        assert!(report.success, "seed {seed}: {:?}", report.failures);
        assert_eq!(report.configuration_matches, Some(true));
        assert_eq!(report.statements_done, 5);
    }
    let unfolded = sim
        .run_model(&ModelRun {
            start: &start,
            expect: Some(&start as &dyn RobotModel),
            scenario: &scenario,
            seed: 1,
            trace: false,
        })
        .expect("runs");
    assert_eq!(
        unfolded.configuration_matches,
        Some(false),
        "the ring is not the line"
    );
}
