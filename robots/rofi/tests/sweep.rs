//! Turns of RoFI modules checked along their whole motion: shapes whose sweeps are known by
//! hand, and on random chains, the check against dense sampling (a sample that overlaps is
//! never in a motion called clear; a reported overlap is one) and lock-step against every
//! timing.

mod common;
use common::{configuration, edge, module};

use dynarole_robot_rofi::{
    sweep, sweep_within, validate, Connection, Dock, Invalid, Joint, Module, Orientation,
    RofiConfiguration, Side, SweepError, SweepVerdict, Timing, Turn,
};
use proptest::prelude::*;

/// `config` with `turns` at `fractions` of their motions.
fn at(config: &RofiConfiguration, turns: &[Turn], fractions: &[f64]) -> RofiConfiguration {
    let mut modules: Vec<Module> = config.modules().copied().collect();
    for (turn, t) in turns.iter().zip(fractions) {
        let m = modules
            .iter_mut()
            .find(|m| m.id == turn.module)
            .expect("the turn's module");
        let angle = turn.from + t * turn.by;
        match turn.joint {
            Joint::Alpha => m.alpha = angle,
            Joint::Beta => m.beta = angle,
            Joint::Gamma => m.gamma = angle,
        }
    }
    configuration(&modules, config.connections())
}

fn overlaps(config: &RofiConfiguration) -> bool {
    matches!(validate(config), Err(Invalid::Collision(_)))
}

#[test]
fn a_module_on_the_end_of_another_swings_clear_of_it() {
    // Shoe B of 2 goes a quarter circle about 2's shoe A, at two units from 1's shoe B at
    // least (the squared distance is 2 + 2 cos of the angle).
    let n = Orientation::North;
    let config = configuration(
        &[module(1, 0.0, 0.0, 0.0), module(2, 0.0, 0.0, 0.0)],
        &[edge(
            (1, Side::B, Dock::MinusZ),
            n,
            (2, Side::A, Dock::MinusZ),
        )],
    );
    for by in [-90.0, 90.0] {
        let turn = Turn {
            module: 2,
            joint: Joint::Alpha,
            from: 0.0,
            by,
        };
        for timing in [Timing::Every, Timing::LockStep] {
            assert_eq!(sweep(&config, &[turn], timing), Ok(SweepVerdict::Clear));
        }
    }
}

#[test]
fn a_module_swung_onto_another_collides_exactly_where_its_end_does() {
    // Module 2 on 1's shoe A (+X dock), 3 on 1's shoe B (-X dock), both pointing along +X:
    // 2's quarter turn ends on 3's shoe A in one direction of the two twists that turn it
    // about the Y axis, and its arc keeps clear of 3 everywhere else.
    let mut collisions = 0;
    for o12 in Orientation::ALL {
        for by in [-90.0, 90.0] {
            let config = configuration(
                &[
                    module(1, 0.0, 0.0, 0.0),
                    module(2, 0.0, 0.0, 0.0),
                    module(3, 0.0, 0.0, 0.0),
                ],
                &[
                    edge((1, Side::A, Dock::PlusX), o12, (2, Side::A, Dock::MinusZ)),
                    edge(
                        (1, Side::B, Dock::MinusX),
                        Orientation::North,
                        (3, Side::A, Dock::MinusZ),
                    ),
                ],
            );
            let turns = [Turn {
                module: 2,
                joint: Joint::Alpha,
                from: 0.0,
                by,
            }];
            let end_overlaps = overlaps(&at(&config, &turns, &[1.0]));
            match sweep(&config, &turns, Timing::Every).expect("checked") {
                SweepVerdict::Clear => assert!(!end_overlaps, "{o12:?} {by}"),
                SweepVerdict::Collides {
                    fractions,
                    collision,
                } => {
                    assert!(end_overlaps, "{o12:?} {by}: {fractions:?} {collision:?}");
                    assert!(overlaps(&at(&config, &turns, &fractions)));
                    collisions += 1;
                }
                other => panic!("{other:?}"),
            }
        }
    }
    assert_eq!(collisions, 2);
}

#[test]
fn a_turn_from_elsewhere_or_out_of_range_is_refused() {
    let config = configuration(&[module(1, 30.0, 0.0, 0.0)], &[]);
    let turn = |from: f64, by: f64| Turn {
        module: 1,
        joint: Joint::Alpha,
        from,
        by,
    };
    assert!(matches!(
        sweep(&config, &[turn(0.0, 10.0)], Timing::Every),
        Err(SweepError::NotAtStart { .. })
    ));
    assert!(matches!(
        sweep(&config, &[turn(30.0, 70.0)], Timing::Every),
        Err(SweepError::OutOfRange(_))
    ));
    assert!(matches!(
        sweep(&config, &[turn(30.0, 10.0), turn(30.0, 5.0)], Timing::Every),
        Err(SweepError::SameJoint(_))
    ));
}

fn any_dock() -> impl Strategy<Value = Dock> {
    prop_oneof![Just(Dock::PlusX), Just(Dock::MinusX), Just(Dock::MinusZ)]
}

fn any_joint() -> impl Strategy<Value = Joint> {
    prop_oneof![Just(Joint::Alpha), Just(Joint::Beta), Just(Joint::Gamma)]
}

/// A chain of four modules, B of each to A of the next, at random docks, twists and angles
/// (multiples of 30 degrees, so that shoes meet often).
fn chain(angles: &[(i8, i8, i8)], links: &[(Dock, usize, Dock)]) -> RofiConfiguration {
    let modules: Vec<Module> = (angles.iter().enumerate())
        .map(|(i, &(a, b, g))| {
            module(
                i as u32 + 1,
                f64::from(a) * 30.0,
                f64::from(b) * 30.0,
                f64::from(g) * 30.0,
            )
        })
        .collect();
    let edges: Vec<Connection> = (links.iter().enumerate())
        .map(|(i, &(d1, o, d2))| {
            let id = i as u32 + 1;
            edge(
                (id, Side::B, d1),
                Orientation::ALL[o % 4],
                (id + 1, Side::A, d2),
            )
        })
        .collect();
    configuration(&modules, &edges)
}

fn turn_of(config: &RofiConfiguration, (m, joint, by): (u32, Joint, i16)) -> Option<Turn> {
    let from = config.module(m)?.joint(joint);
    let by = f64::from(by);
    let end = from + by;
    if joint != Joint::Gamma && end.abs() > 90.0 {
        return None;
    }
    Some(Turn {
        module: m,
        joint,
        from,
        by,
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn no_sampled_overlap_is_in_a_motion_called_clear(
        angles in proptest::collection::vec((-3i8..=3, -3i8..=3, -6i8..6), 4),
        links in proptest::collection::vec((any_dock(), 0usize..4, any_dock()), 3),
        picks in proptest::collection::vec((1u32..=4, any_joint(), -180i16..=180), 1..3),
    ) {
        let config = chain(&angles, &links);
        prop_assume!(validate(&config).is_ok());
        let mut turns: Vec<Turn> = Vec::new();
        for pick in picks {
            if let Some(turn) = turn_of(&config, pick) {
                if !turns.iter().any(|t| t.module == turn.module && t.joint == turn.joint) {
                    turns.push(turn);
                }
            }
        }
        prop_assume!(!turns.is_empty());
        // A small budget: "unproven" is not "clear", which is all the samples can contradict.
        let every = sweep_within(&config, &turns, Timing::Every, 5_000).expect("checked");
        let lockstep = sweep_within(&config, &turns, Timing::LockStep, 5_000).expect("checked");
        // Dense samples of the box (every timing) and of its diagonal (lock-step).
        let steps = 24;
        let grid: Vec<Vec<f64>> = match turns.len() {
            1 => (0..=steps).map(|i| vec![f64::from(i) / f64::from(steps)]).collect(),
            _ => (0..=steps)
                .flat_map(|i| (0..=steps).map(move |k| vec![f64::from(i) / f64::from(steps), f64::from(k) / f64::from(steps)]))
                .collect(),
        };
        let sampled = grid.iter().find(|f| overlaps(&at(&config, &turns, f)));
        let diagonal = (0..=steps)
            .map(|i| vec![f64::from(i) / f64::from(steps); turns.len()])
            .find(|f| overlaps(&at(&config, &turns, f)));
        if let Some(f) = sampled {
            prop_assert!(every != SweepVerdict::Clear, "{turns:?} overlap at {f:?}");
        }
        if let Some(f) = diagonal {
            prop_assert!(lockstep != SweepVerdict::Clear, "{turns:?} overlap at {f:?}");
        }
        for verdict in [&every, &lockstep] {
            if let SweepVerdict::Collides { fractions, .. } = verdict {
                prop_assert!(overlaps(&at(&config, &turns, fractions)), "{verdict:?}");
            }
        }
        // Lock-step is one path through the box: clear over every timing, it is clear, or
        // (its pieces do not follow the box's) not decided within the budget.
        if every == SweepVerdict::Clear {
            let decided_clear = lockstep == SweepVerdict::Clear;
            let unproven = matches!(lockstep, SweepVerdict::Unproven { .. });
            prop_assert!(decided_clear || unproven, "lock-step: {:?}", lockstep);
        }
    }
}
