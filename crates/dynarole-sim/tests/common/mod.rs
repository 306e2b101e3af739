//! Shared by the simulator's tests: compile a sequence from source and run it.
#![allow(dead_code)]

pub mod counting;
pub mod faults;
pub mod grid;

use dynarole_codegen::{CompileOptions, Protocol};
use dynarole_core::{driver, parse};
use dynarole_sim::{Report, Run, Scenario, Simulator};
use dynarole_world::Configuration;

pub const EIGHT2CAR: &str = include_str!("../../../../robots/atron/examples/eight2car.dr");
pub const EIGHT: &str = include_str!("../../../../robots/atron/examples/eight.json");
pub const CAR: &str = include_str!("../../../../robots/atron/examples/car.json");

pub fn options(protocol: Protocol) -> CompileOptions {
    CompileOptions {
        protocol,
        name: "test".into(),
        ..CompileOptions::default()
    }
}

pub fn config(text: &str) -> Configuration {
    dynarole_robots::read_configuration(text).expect("valid configuration")
}

pub fn simulator(source: &str, sequences: &[&str], protocol: Protocol) -> Simulator {
    let parsed = parse(source);
    let program = driver::check(&parsed, &dynarole_robots::plugins())
        .unwrap_or_else(|diagnostics| panic!("{diagnostics:?}"));
    let names: Vec<String> = sequences.iter().map(|s| s.to_string()).collect();
    let plans = driver::plans(&program, &names).expect("sequences exist");
    Simulator::new(&program, &plans, &options(protocol)).expect("compiles")
}

pub fn run(
    sim: &Simulator,
    start: &str,
    expect: Option<&str>,
    scenario: &Scenario,
    seed: u64,
) -> Report {
    let start = config(start);
    let expect = expect.map(config);
    sim.run(&Run {
        start: &start,
        expect: expect.as_ref(),
        scenario,
        seed,
        trace: true,
    })
    .expect("runs")
}

pub fn eight2car(protocol: Protocol, scenario: &Scenario, seed: u64) -> Report {
    let sim = simulator(EIGHT2CAR, &["eight2car"], protocol);
    run(&sim, EIGHT, Some(CAR), scenario, seed)
}

/// Whether `field`, what a lattice module's description shows after `run` (`N`, or `N+<hex>`
/// for a batch: bit k = statement N + 1 + k), holds `statement`.
pub fn runs_statement(field: &str, statement: usize) -> bool {
    let (first, others) = field.split_once('+').unwrap_or((field, "0"));
    let (Ok(first), Ok(others)) = (first.parse::<usize>(), u32::from_str_radix(others, 16)) else {
        return false;
    };
    statement == first
        || (statement > first
            && statement - first <= 32
            && (others >> (statement - first - 1)) & 1 == 1)
}
