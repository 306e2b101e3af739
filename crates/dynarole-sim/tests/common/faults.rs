//! Random faults for the simulator's property tests: resets, a power cycle and a blocked link
//! in the first part of a run, drawn in one fixed order so that a seed means one scenario.

use dynarole_sim::{Block, Power, Reset, Scenario};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use std::ops::RangeInclusive;

/// Adds `resets` resets (a count drawn from the range), then with probability 1/2 a power
/// cycle and with probability 1/2 a blocked link, each of a module of `modules` within the
/// first `span_ms`.
pub fn add_module_faults(
    rng: &mut ChaCha8Rng,
    scenario: &mut Scenario,
    modules: &[&str],
    span_ms: u64,
    resets: RangeInclusive<i32>,
) {
    let module = |rng: &mut ChaCha8Rng| modules[rng.random_range(0..modules.len())].to_string();
    for _ in 0..rng.random_range(resets) {
        scenario.reset.push(Reset {
            module: module(rng),
            at_ms: rng.random_range(0..span_ms),
        });
    }
    if rng.random_bool(0.5) {
        let off_ms = rng.random_range(0..span_ms);
        scenario.power.push(Power {
            module: module(rng),
            off_ms,
            on_ms: off_ms + rng.random_range(10..3_000),
        });
    }
    if rng.random_bool(0.5) {
        let from_ms = rng.random_range(0..span_ms);
        scenario.block.push(Block {
            module: module(rng),
            connector: rng.random_range(0..8),
            from_ms,
            to_ms: from_ms + rng.random_range(100..5_000),
        });
    }
}
