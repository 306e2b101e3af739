//! Benchmark: a group of joint turns checked along its whole motion on a straight chain of
//! RoFI modules, over every relative timing and in lock-step.

use criterion::{criterion_group, criterion_main, Criterion};
use dynarole_robot_rofi::{
    sweep, Connection, Connector, Dock, Joint, Module, Orientation, RofiConfiguration, Side,
    SweepVerdict, Timing, Turn,
};

/// `n` straight modules, B of each on A of the next (-Z to -Z).
fn chain(n: u32) -> RofiConfiguration {
    let mut config = RofiConfiguration::new();
    for id in 1..=n {
        let module = Module {
            id,
            alpha: 0.0,
            beta: 0.0,
            gamma: 0.0,
        };
        config.add_module(module).expect("a module");
    }
    for id in 1..n {
        let connection = Connection {
            from: (id, Connector::new(Side::B, Dock::MinusZ)),
            orientation: Orientation::North,
            to: (id + 1, Connector::new(Side::A, Dock::MinusZ)),
        };
        config.connect(connection).expect("a connection");
    }
    config
}

/// Alpha of modules 2, 4, 6, ... (`k` of them) turned by `by` degrees at once: the chain
/// folds into a zigzag (or a spiral) that stays clear of itself.
fn turns(k: u32, by: f64) -> Vec<Turn> {
    (0..k)
        .map(|i| Turn {
            module: 2 + 2 * i,
            joint: Joint::Alpha,
            from: 0.0,
            by,
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    for (n, k, by) in [(6, 2, 90.0), (8, 3, 90.0), (10, 4, 60.0), (20, 6, 45.0)] {
        let config = chain(n);
        let group = turns(k, by);
        for timing in [Timing::Every, Timing::LockStep] {
            let verdict = sweep(&config, &group, timing).expect("checked");
            assert_eq!(
                verdict,
                SweepVerdict::Clear,
                "{n} modules, {k} turns, {timing:?}"
            );
            let name = format!("sweep {k} turns of {by} degrees on a chain of {n}, {timing:?}");
            c.bench_function(&name, |b| b.iter(|| sweep(&config, &group, timing)));
        }
    }
}

criterion_group! {
    name = sweep_benches;
    config = Criterion::default().sample_size(10);
    targets = benches
}
criterion_main!(sweep_benches);
