//! A plan's consecutive configurations as steps: turns alone, together over any timing, and
//! a loop of two modules that turns only in lock-step; connections released and made; and
//! each way a step can be refused, the plan naming the step.

mod common;
use common::{configuration, edge, module};

use dynarole_robot_rofi::{
    plan_steps, plan_steps_at, poses, read_old_format, step_between, Connection, Dock, Joint,
    Module, Orientation, RofiConfiguration, Side, StepError, SweepVerdict, Together,
};

/// Straight modules 1..=n, B of each on A of the next.
fn chain(angles: &[(f64, f64, f64)]) -> RofiConfiguration {
    let modules: Vec<Module> = (angles.iter().enumerate())
        .map(|(i, &(a, b, g))| module(i as u32 + 1, a, b, g))
        .collect();
    let edges: Vec<Connection> = (1..angles.len() as u32)
        .map(|id| {
            let n = Orientation::North;
            edge(
                (id, Side::B, Dock::MinusZ),
                n,
                (id + 1, Side::A, Dock::MinusZ),
            )
        })
        .collect();
    configuration(&modules, &edges)
}

#[test]
fn one_turn_is_a_step_alone_and_two_apart_run_at_any_timing() {
    let straight = chain(&[(0.0, 0.0, 0.0); 4]);
    let bent = chain(&[
        (0.0, 0.0, 0.0),
        (90.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
    ]);
    let step = step_between(&straight, &bent).expect("a step");
    assert_eq!(step.together, Together::Alone);
    assert_eq!(step.turns.len(), 1);
    assert_eq!(
        (step.turns[0].module, step.turns[0].joint),
        (2, Joint::Alpha)
    );
    let zigzag = chain(&[
        (0.0, 0.0, 0.0),
        (45.0, 0.0, 0.0),
        (0.0, 0.0, 0.0),
        (-45.0, 0.0, 0.0),
    ]);
    let step = step_between(&straight, &zigzag).expect("a step");
    assert_eq!(step.together, Together::AnyTiming);
    assert_eq!(step.turns.len(), 2);
}

#[test]
fn gamma_turns_the_short_way_round() {
    let from = chain(&[(0.0, 0.0, 170.0), (0.0, 0.0, 0.0)]);
    let to = chain(&[(0.0, 0.0, -170.0), (0.0, 0.0, 0.0)]);
    let step = step_between(&from, &to).expect("a step");
    assert!((step.turns[0].by - 20.0).abs() < 1e-9, "{:?}", step.turns);
}

/// Two straight modules side by side, joined at shoe A (1's +X to 2's `da`, twist `oa`):
/// with the shoe B connection (`d1`, `ob`, `d2`) when `closed`.
fn side_by_side(
    (da, oa): (Dock, Orientation),
    (d1, ob, d2): (Dock, Orientation, Dock),
    alphas: (f64, f64),
    closed: bool,
) -> Option<RofiConfiguration> {
    let mut edges = vec![edge((1, Side::A, Dock::PlusX), oa, (2, Side::A, da))];
    if closed {
        edges.push(edge((1, Side::B, d1), ob, (2, Side::B, d2)));
    }
    let modules = [module(1, alphas.0, 0.0, 0.0), module(2, alphas.1, 0.0, 0.0)];
    RofiConfiguration::from_parts(&modules, &edges).ok()
}

type Twists = ((Dock, Orientation), (Dock, Orientation, Dock));

/// The twists of `side_by_side` whose square closes, and those whose does not.
fn squares() -> (Vec<Twists>, Vec<Twists>) {
    let docks = [Dock::PlusX, Dock::MinusX];
    let (mut closing, mut open) = (Vec::new(), Vec::new());
    for da in docks {
        for oa in Orientation::ALL {
            for d1 in docks {
                for d2 in docks {
                    for ob in Orientation::ALL {
                        let twists = ((da, oa), (d1, ob, d2));
                        let square = side_by_side(twists.0, twists.1, (0.0, 0.0), true);
                        match square.map(|c| poses(&c).is_ok()) {
                            Some(true) => closing.push(twists),
                            _ => open.push(twists),
                        }
                    }
                }
            }
        }
    }
    (closing, open)
}

#[test]
fn a_connection_is_made_only_between_mated_connectors() {
    let (closing, open) = squares();
    assert!(!closing.is_empty() && !open.is_empty());
    for (a, b) in closing {
        let before = side_by_side(a, b, (0.0, 0.0), false).expect("open square");
        let after = side_by_side(a, b, (0.0, 0.0), true).expect("closed square");
        let step = step_between(&before, &after).expect("a connect");
        assert_eq!(step.connects.len(), 1);
        assert!(step.turns.is_empty() && step.disconnects.is_empty());
        // And back: a release that keeps the robot whole.
        let back = step_between(&after, &before).expect("a disconnect");
        assert_eq!(back.disconnects.len(), 1);
    }
    for (a, b) in open {
        let before = side_by_side(a, b, (0.0, 0.0), false).expect("open square");
        let Some(after) = side_by_side(a, b, (0.0, 0.0), true) else {
            continue;
        };
        let refused = step_between(&before, &after);
        assert!(
            matches!(refused, Err(StepError::NotMated(..))),
            "{refused:?}"
        );
    }
}

#[test]
fn a_closed_square_turns_only_in_lock_step_and_only_one_way() {
    // The two modules' alpha axes are one line through both shoes A: turned together by the
    // same physical angle, the square stays closed; either alone (any other timing) pulls
    // shoe B of 2 away from shoe B of 1.
    let (closing, _) = squares();
    for (a, b) in closing {
        let before = side_by_side(a, b, (0.0, 0.0), true).expect("closed");
        let mut lockstep = 0;
        for second in [45.0, -45.0] {
            let Some(after) = side_by_side(a, b, (45.0, second), true) else {
                continue;
            };
            match step_between(&before, &after) {
                Ok(step) => {
                    assert_eq!(step.together, Together::LockStep, "{a:?} {b:?}");
                    lockstep += 1;
                }
                Err(StepError::Turns(SweepVerdict::OpensLoop { .. })) => {}
                Err(other) => panic!("{a:?} {b:?} {second}: {other:?}"),
            }
        }
        assert_eq!(lockstep, 1, "{a:?} {b:?}");
    }
}

#[test]
fn each_refusal_says_why() {
    let two = chain(&[(0.0, 0.0, 0.0); 2]);
    let apart = configuration(&[module(1, 0.0, 0.0, 0.0), module(2, 0.0, 0.0, 0.0)], &[]);
    assert!(matches!(
        step_between(&two, &apart),
        Err(StepError::Splits(_))
    ));
    assert_eq!(step_between(&two, &two), Err(StepError::Nothing));
    let three = chain(&[(0.0, 0.0, 0.0); 3]);
    assert_eq!(
        step_between(&two, &three),
        Err(StepError::ModulesDiffer {
            missing: vec![],
            added: vec![3]
        })
    );
    // Module 2 on 1's shoe A, 3 on its shoe B, both pointing along +X: 2's quarter turn
    // the wrong way ends on 3.
    let bent_onto = |o12: Orientation, alpha: f64| {
        configuration(
            &[
                module(1, 0.0, 0.0, 0.0),
                module(2, alpha, 0.0, 0.0),
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
        )
    };
    let refused: Vec<StepError> = (Orientation::ALL.iter())
        .flat_map(|&o| [90.0, -90.0].map(|alpha| (o, alpha)))
        .filter_map(|(o, alpha)| step_between(&bent_onto(o, 0.0), &bent_onto(o, alpha)).err())
        .collect();
    assert_eq!(refused.len(), 2, "{refused:?}");
    for e in &refused {
        assert!(
            matches!(e, StepError::Turns(SweepVerdict::Collides { .. })),
            "{e:?}"
        );
        // One turn: nothing of lock-step to say, only where along it the shoes meet.
        assert!(e.to_string().starts_with("the turn brings"), "{e}");
        assert!(e.to_string().contains("of its motion"), "{e}");
    }
}

#[test]
fn a_plan_read_from_the_old_format_names_the_step_that_fails() {
    let text = "C\nM 1 0 0 0\nM 2 0 0 0\nE 1 B -Z N -Z A 2\n\
                C\nM 1 0 0 0\nM 2 90 0 0\nE 1 B -Z N -Z A 2\n\
                C\nM 1 0 0 0\nM 2 90 0 0\n";
    let plan = read_old_format(text).expect("a plan");
    let configurations: Vec<RofiConfiguration> =
        plan.configurations.into_iter().map(|(_, c)| c).collect();
    match plan_steps(&configurations) {
        Err((1, StepError::Splits(_))) => {}
        other => panic!("{other:?}"),
    }
    let steps = plan_steps(&configurations[..2]).expect("one step");
    assert_eq!(steps.len(), 1);
    // Named by the configuration that cannot be reached, and its line.
    let plan = read_old_format(text).expect("a plan");
    let error = plan_steps_at(&plan.configurations).expect_err("refused");
    assert_eq!((error.configuration, error.line), (2, 9));
    let message = error.to_string();
    assert!(
        message.starts_with("configuration 2 (line 9), the step from configuration 1"),
        "{message}"
    );
    // A first configuration that is not valid is named itself.
    let invalid = "C\nM 1 0 0 0\nM 2 0 0 0\nE 1 A -Z N -Z A 2\nE 1 B -Z N -Z B 2\n";
    let plan = read_old_format(invalid).expect("a plan");
    let error = plan_steps_at(&plan.configurations).expect_err("refused");
    assert_eq!((error.configuration, error.line), (0, 1));
    assert!(
        error.to_string().contains("a loop does not close"),
        "{error}"
    );
}

#[test]
fn a_half_turn_of_gamma_is_given_a_direction_and_a_note() {
    // Module 2 bent, module 1's gamma turned half round: the file cannot say which way.
    let from = chain(&[(0.0, 0.0, 0.0), (90.0, 0.0, 0.0)]);
    let to = chain(&[(0.0, 0.0, 180.0), (90.0, 0.0, 0.0)]);
    let step = step_between(&from, &to).expect("a step");
    assert_eq!(step.turns.len(), 1);
    assert_eq!(step.turns[0].by.abs(), 180.0);
    assert!(
        step.notes.iter().any(|n| n.contains("half round")),
        "{:?}",
        step.notes
    );
}
