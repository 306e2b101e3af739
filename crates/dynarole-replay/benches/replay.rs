//! Benchmark: replay of the paper's eight2car, of a 1,000-statement sequence on a generated
//! 10,000-module ATRON chain, and the independence check of a group whose completion orders
//! are all checked (the eight's eight latches released at once: 2^8 sets).

use criterion::{criterion_group, criterion_main, Criterion};
use dynarole_core::{analyze, parse};
use dynarole_replay::{assign_modules, check_independence, replay, RobotWorld};
use dynarole_robot_atron::generated::atron_chain_json;

const FIG5: &str = include_str!("../../../robots/atron/examples/eight2car.dr");
const EIGHT: &str = include_str!("../../../robots/atron/examples/eight.json");

/// 1,000 statements: latches in the middle released and re-made, and the last joints turned
/// back and forth (each turn moves the short end, checked against all 10,000 modules).
fn chain_sequence(n: usize) -> String {
    let mut body = String::new();
    for i in 0..250 {
        let k = n / 2 + 1 + 2 * (i % 100);
        body.push_str(&format!("    M{k}.Connector[$CONNECTOR_0].retract();\n    M{k}.Connector[$CONNECTOR_0].extend();\n"));
        let m = n - 2;
        body.push_str(&format!(
            "    M{m}.Joint.rotateFromToBy(0, 108, true, 150);\n    M{m}.Joint.rotateFromToBy(108, 0, false, 150);\n"
        ));
    }
    format!("robot atron;\nsequence big {{\n{body}}}\n")
}

fn bench_replay(c: &mut Criterion, name: &str, source: &str, config: &str, sequence: &str) {
    let registry = dynarole_robots::plugins();
    let parsed = parse(source);
    let (program, diagnostics) = analyze(&parsed.file, &registry);
    let program = program.unwrap_or_else(|| panic!("{name}: {diagnostics:?}"));
    let config =
        dynarole_robots::read_configuration(config).unwrap_or_else(|e| panic!("{name}: {e}"));
    let plans = vec![program
        .expand(sequence)
        .unwrap_or_else(|| panic!("{name}: no {sequence}"))];
    let assignment =
        assign_modules(&program, &plans, &config).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let world = RobotWorld::new(config, &program.robot).unwrap_or_else(|e| panic!("{name}: {e}"));
    let check = replay(&program, &plans, world.clone(), &assignment);
    assert_eq!(
        check.n_rejected,
        0,
        "{name}: {:?}",
        check.diagnostics.first()
    );
    c.bench_function(name, |b| {
        b.iter(|| replay(&program, &plans, world.clone(), &assignment))
    });
}

/// The eight's releasable latches (each alone keeps the robot whole) joined in one group of
/// `k`: every pair gives the same warnings in either order, so the group's completion orders
/// decide it (`k` · 2^(k−1) steps).
fn releases(k: usize) -> String {
    let latches = [
        "M0.Connector[$CONNECTOR_0]",
        "M0.Connector[$CONNECTOR_4]",
        "M3.Connector[$CONNECTOR_0]",
        "M3.Connector[$CONNECTOR_2]",
        "M3.Connector[$CONNECTOR_4]",
        "M3.Connector[$CONNECTOR_6]",
        "M6.Connector[$CONNECTOR_2]",
        "M6.Connector[$CONNECTOR_6]",
    ];
    let ops: Vec<String> = (latches.iter().take(k))
        .map(|l| format!("    {l}.retract()"))
        .collect();
    format!("robot atron;\nsequence s {{\n{};\n}}\n", ops.join(" &\n"))
}

fn bench_orders(c: &mut Criterion, k: usize) {
    let registry = dynarole_robots::plugins();
    let source = releases(k);
    let parsed = parse(&source);
    let program = analyze(&parsed.file, &registry)
        .0
        .expect("the releases check");
    let config = dynarole_robots::read_configuration(EIGHT).expect("the eight");
    let plans = vec![program.expand("s").expect("s")];
    let assignment = assign_modules(&program, &plans, &config).expect("labels");
    let world = RobotWorld::new(config, &program.robot).expect("world");
    let name = format!("independence of {k} releases on the eight, every completion order");
    c.bench_function(&name, |b| {
        b.iter(|| check_independence(&program, &plans, world.clone(), &assignment))
    });
}

fn benches(c: &mut Criterion) {
    for k in [4, 6, 8] {
        bench_orders(c, k);
    }
    bench_replay(
        c,
        "replay eight2car (25 statements, 7 modules)",
        FIG5,
        EIGHT,
        "eight2car",
    );
    let n = 10_000;
    let config = atron_chain_json(n);
    let started = std::time::Instant::now();
    let loaded = dynarole_robots::read_configuration(&config);
    assert!(loaded.is_ok());
    println!("load a {n}-module configuration: {:?}", started.elapsed());
    bench_replay(
        c,
        "replay 1,000 statements on a 10,000-module chain",
        &chain_sequence(n),
        &config,
        "big",
    );
}

criterion_group! {
    name = replay_benches;
    config = Criterion::default().sample_size(10);
    targets = benches
}
criterion_main!(replay_benches);
