//! The example plans of `robots/rofi/examples/` (and of `tests/plans/`), written for dynarole:
//! each reads, every step is checked and classed as expected, and the plan run backwards (the
//! derived reverse of each step) is valid too.

use dynarole_robot_rofi::{plan_steps, read_old_format, RofiConfiguration, Step, Together};

fn configurations(name: &str) -> Vec<RofiConfiguration> {
    let path = format!("{}/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let plan = read_old_format(&text).unwrap_or_else(|e| panic!("{path}: {e}"));
    plan.configurations.into_iter().map(|(_, c)| c).collect()
}

/// The steps forwards, and the steps of the same plan backwards.
fn both_ways(name: &str) -> (Vec<Step>, Vec<Step>) {
    let forwards = configurations(name);
    let mut backwards = forwards.clone();
    backwards.reverse();
    let steps = |c: &[RofiConfiguration]| {
        plan_steps(c).unwrap_or_else(|(i, e)| panic!("{name}: step {i}: {e}"))
    };
    (steps(&forwards), steps(&backwards))
}

fn classes(steps: &[Step]) -> Vec<Together> {
    steps.iter().map(|s| s.together).collect()
}

#[test]
fn the_gamma_swing_is_three_single_turns_both_ways() {
    let (forwards, backwards) = both_ways("examples/gamma-swing.txt");
    assert_eq!(classes(&forwards), [Together::Alone; 3]);
    assert_eq!(classes(&backwards), [Together::Alone; 3]);
    assert!(forwards
        .iter()
        .all(|s| s.turns.len() == 1 && s.notes.is_empty()));
}

#[test]
fn the_folded_chain_turns_only_in_lock_step_both_ways() {
    let (forwards, backwards) = both_ways("examples/fold-sync.txt");
    assert_eq!(classes(&forwards), [Together::LockStep]);
    assert_eq!(classes(&backwards), [Together::LockStep]);
    assert_eq!(forwards[0].turns.len(), 2);
}

/// A loop of two modules kept closed only by turning both alphas exactly together: RoFI's
/// check allows it; dynarole's model, which applies one turn at a time, refuses the loop
/// opening (`dynarole import` says so).
#[test]
fn the_square_turns_only_in_lock_step_both_ways() {
    let (forwards, backwards) = both_ways("tests/plans/square-lockstep.txt");
    assert_eq!(classes(&forwards), [Together::LockStep]);
    assert_eq!(classes(&backwards), [Together::LockStep]);
}

#[test]
fn the_snake_folds_at_any_timing_and_closes_into_a_ring() {
    // The fold's four turns are proven clear over every relative timing, though two shoes end
    // touching (the second-order bound proves them to within the tolerance).
    let (forwards, backwards) = both_ways("examples/snake-to-ring.txt");
    assert_eq!(classes(&forwards), [Together::AnyTiming, Together::Alone]);
    assert_eq!(forwards[0].turns.len(), 4);
    assert_eq!(forwards[1].connects.len(), 1);
    // Backwards the ring opens first, then unfolds.
    assert_eq!(backwards[0].disconnects.len(), 1);
    assert_eq!(classes(&backwards), [Together::Alone, Together::AnyTiming]);
}

/// A synchronous group's start skew as a band of timings: the fold's two turns are clear when
/// their fractions stay close, collide when they may drift as far as every timing lets them,
/// and a collision found within a band is at a timing of it.
#[test]
fn the_folded_chain_is_clear_within_a_narrow_band_and_collides_within_a_wide_one() {
    use dynarole_robot_rofi::{sweep, SweepVerdict, Timing};
    let plan = configurations("examples/fold-sync.txt");
    let (steps, _) = both_ways("examples/fold-sync.txt");
    let turns = &steps[0].turns;
    assert_eq!(
        sweep(&plan[0], turns, Timing::Band(0.05)),
        Ok(SweepVerdict::Clear)
    );
    for width in [0.5, 1.0] {
        match sweep(&plan[0], turns, Timing::Band(width)) {
            Ok(SweepVerdict::Collides { fractions, .. }) => {
                let spread = fractions.iter().copied().fold(f64::MIN, f64::max)
                    - fractions.iter().copied().fold(f64::MAX, f64::min);
                assert!(spread <= width, "{fractions:?} outside the band {width}");
            }
            other => panic!("band {width}: {other:?}"),
        }
    }
}
