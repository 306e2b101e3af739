//! A robot defined outside the tool's crates (the hinged cubes of the `dynarole-cli` crate's
//! `hinged_cubes` example, its one copy) goes through the tool's libraries: the checker with
//! its plugin, the replay and independence check on its model, and the simulator running the
//! generated C on every cube, each reaching the expected ring.

// Parts of the robot only its program uses (the kind's drawing, say) are unused here.
#[allow(dead_code)]
#[path = "../../dynarole-cli/examples/hinged_cubes/robot/mod.rs"]
mod hinged_cubes;

use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{driver, parse, Program, RobotApi};
use dynarole_replay::{assign_modules_on, check_independence, replay, RobotWorld};
use dynarole_sim::{ModelRun, Scenario, Simulator};
use dynarole_world::{RobotKind, RobotModel};

/// A program for it: fold a line of four cubes into a closed ring, and back.
const RING: &str = include_str!("../../dynarole-cli/examples/hinged_cubes/ring.dr");

fn plugin() -> RobotApi {
    RobotApi::from_toml(hinged_cubes::KIND.plugin().1).expect("the robot's plugin loads")
}

/// The model that starts from one of the robot's data files.
fn model(json: &str) -> Box<dyn RobotModel> {
    let config = hinged_cubes::KIND.read_configuration(json);
    config.expect("a cubes data file").into_model()
}

/// The line of four cubes, each latched to the next.
fn line4() -> Box<dyn RobotModel> {
    model(include_str!(
        "../../dynarole-cli/examples/hinged_cubes/line4.json"
    ))
}

/// The line folded into a closed ring.
fn ring4() -> Box<dyn RobotModel> {
    model(include_str!(
        "../../dynarole-cli/examples/hinged_cubes/ring4.json"
    ))
}

/// `source` checked by the program driver, with the plugin found beside it.
fn check(parsed: &dynarole_core::Parsed) -> Program<'_> {
    let registry = driver::registry(
        dynarole_robots::plugins(),
        driver::robot_name(&parsed.file),
        [],
        |file| {
            assert_eq!(file, "hinged.robot.toml");
            Ok::<_, ()>(Some(plugin()))
        },
    )
    .expect("registry");
    driver::check(parsed, &registry).unwrap_or_else(|d| panic!("{d:?}"))
}

/// `sequence` replayed on `start`; the end, and every diagnostic of the replay and of the
/// independence check.
fn replayed(
    program: &Program,
    sequence: &str,
    start: Box<dyn RobotModel>,
) -> (RobotWorld, Vec<String>) {
    let plans = driver::plans(program, &[sequence.to_string()]).expect("sequence");
    let world = RobotWorld::from_model(start, &program.robot).expect("a cubes model");
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
    let (end, problems) = replayed(&program, "ring", line4());
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(end.model().difference(ring4().as_ref()), None);
    assert_eq!(
        end.view()
            .latched_to(dynarole_world::Port {
                module: 3,
                connector: 0
            })
            .map(|p| p.module),
        Some(0)
    );
    let (back, problems) = replayed(&program, "open", ring4());
    assert!(problems.is_empty(), "{problems:?}");
    assert_eq!(back.model().difference(line4().as_ref()), None);
}

#[test]
fn the_model_refuses_what_the_cubes_cannot_do() {
    let source = RING.replace(
        "    M0.Hinge.bend(0, 90, true, 100);\n",
        "    M3.Connector[$FRONT].latch();\n",
    );
    let parsed = parse(&source);
    let program = check(&parsed);
    let (end, problems) = replayed(&program, "ring", line4());
    assert!(
        problems.iter().any(|p| p.contains("nothing to latch onto")),
        "latching before the ring is closed: {problems:?}"
    );
    assert!(end.model().difference(ring4().as_ref()).is_some());
    let locked = RING.replace(
        "sequence open = reverse ring;",
        "sequence more {\n    M0.Hinge.bend(90, 0, false, 100);\n}",
    );
    let parsed = parse(&locked);
    let program = check(&parsed);
    let (_, problems) = replayed(&program, "more", ring4());
    assert!(problems.iter().any(|p| p.contains("loop")), "{problems:?}");
}

#[test]
fn a_model_of_another_robot_is_refused() {
    let atron = dynarole_robots::plugins()
        .get("atron")
        .cloned()
        .expect("built in");
    let refused = RobotWorld::from_model(line4(), &atron).expect_err("not atron");
    assert!(refused.contains("robot `hinged`"), "{refused}");
}

#[test]
fn the_generated_c_folds_the_ring_on_every_cube() {
    let parsed = parse(RING);
    let program = check(&parsed);
    let plans = driver::plans(&program, &["ring".to_string()]).expect("ring");
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "hinged".into(),
        ..CompileOptions::default()
    };
    let sim = Simulator::new(&program, &plans, &options).expect("compiles");
    let (start, ring) = (line4(), ring4());
    let (start, ring) = (start.as_ref(), ring.as_ref());
    let scenario = Scenario::default();
    for seed in [1, 2] {
        let report = sim
            .run_model(&ModelRun {
                start,
                expect: Some(ring),
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
            start,
            expect: Some(start),
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

/// How long statement `s` took in a run of the ring on the cubes under `timing` (a scenario's
/// `[timing]` table), in ms; `Err` for a scenario the run refuses.
fn ring_statement_ms(timing: &str, s: usize) -> Result<f64, String> {
    let parsed = parse(RING);
    let program = check(&parsed);
    let plans = driver::plans(&program, &["ring".to_string()]).expect("ring");
    let options = CompileOptions {
        protocol: Protocol::Lattice,
        name: "hinged".into(),
        ..CompileOptions::default()
    };
    let sim = Simulator::new(&program, &plans, &options).expect("compiles");
    let scenario = Scenario::from_toml_str(timing).map_err(|e| e.to_string())?;
    let start = line4();
    let report = sim
        .run_model(&ModelRun {
            start: start.as_ref(),
            expect: None,
            scenario: &scenario,
            seed: 1,
            trace: true,
        })
        .map_err(|e| e.to_string())?;
    let trace = report.trace.unwrap_or_default();
    let when = |event: &str| {
        let tag = format!("#{s} ");
        (trace.lines())
            .find(|line| line.split_whitespace().nth(2) == Some(event) && line.contains(&tag))
            .and_then(|line| line.split_whitespace().next()?.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no {event} of #{s}:\n{trace}"))
    };
    Ok((when("done") - when("start")).round())
}

/// The cubes declare their own timing presets (`hinged.robot.toml`): a bend of a quarter turn
/// takes the first one's 0.8 s, the `geared` one's 2.5 s, and ATRON's `ussr` is not theirs.
#[test]
fn the_cubes_own_timing_presets_time_their_bends() {
    assert_eq!(ring_statement_ms("", 0), Ok(800.0));
    assert_eq!(
        ring_statement_ms("[timing]\npreset = \"servo\"\n", 0),
        Ok(800.0)
    );
    assert_eq!(
        ring_statement_ms("[timing]\npreset = \"geared\"\n", 0),
        Ok(2_500.0)
    );
    assert_eq!(
        ring_statement_ms("[timing]\npreset = \"geared\"\nextend_ms = 700\n", 4),
        Ok(700.0),
        "the latch, with the scenario's extend_ms"
    );
    let refused = ring_statement_ms("[timing]\npreset = \"ussr\"\n", 0).expect_err("not theirs");
    assert!(
        refused.contains("robot `hinged` has `servo` and `geared`"),
        "{refused}"
    );
}
