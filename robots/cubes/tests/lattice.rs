//! The cube lattice through its public interface: every variant of every move accepted where
//! it holds and refused when one of its cells changes, moves undone by their reverse and
//! animated to their destination on random robots, articulation points, and each parallel rule
//! refusing a set made for it.

use dynarole_robot_cubes::lattice::{
    Cell, Dir, Lattice, LatticeError, Move, MoveError, SetError, Underway,
};
use dynarole_world::Motion;
use proptest::prelude::*;
use std::collections::BTreeSet;

fn name(m: usize) -> String {
    format!("M{m}")
}

fn lattice(positions: &[Cell], fixed: &[bool]) -> Lattice {
    Lattice::new(positions.to_vec(), fixed.to_vec()).expect("a valid lattice")
}

/// Module 0 free at the origin, the others fixed at `fixed` (so joined through the ground).
fn mover_among(fixed: &[Cell]) -> Lattice {
    let positions: Vec<Cell> = std::iter::once([0, 0, 0])
        .chain(fixed.iter().copied())
        .collect();
    let flags: Vec<bool> = (0..positions.len()).map(|m| m > 0).collect();
    lattice(&positions, &flags)
}

fn without(cells: &[Cell], cell: Cell) -> Vec<Cell> {
    cells.iter().copied().filter(|&c| c != cell).collect()
}

fn end_of(mv: &Move, start: [f64; 3]) -> [f64; 3] {
    let motion = Motion {
        legs: mv.legs(start),
        ..Motion::in_place()
    };
    motion.position_at(start, 1.0)
}

fn assert_near(point: [f64; 3], cell: Cell) {
    for k in 0..3 {
        assert!(
            (point[k] - f64::from(cell[k])).abs() < 1e-9,
            "{point:?} is not at {cell:?}"
        );
    }
}

fn plus(a: Cell, b: Cell) -> Cell {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[test]
fn directions_know_their_codes_vectors_and_names() {
    let names: Vec<&str> = Dir::ALL.iter().map(|d| d.name()).collect();
    assert_eq!(names, ["+x", "-x", "+y", "-y", "+z", "-z"]);
    for dir in Dir::ALL {
        assert_eq!(Dir::from_code(dir.code()), Some(dir));
        assert_eq!(Dir::from_vector(dir.vector()), Some(dir));
        assert_eq!(dir.reversed().vector(), dir.vector().map(|c| -c));
        assert!(!dir.is_perpendicular(dir.reversed()));
    }
    assert_eq!(Dir::from_code(-2), Some(Dir::MINUS_Y));
    assert_eq!(Dir::from_code(0), None);
    assert_eq!(Dir::from_code(4), None);
    assert_eq!(Dir::from_vector([1, 1, 0]), None);
    assert!(Dir::PLUS_X.is_perpendicular(Dir::MINUS_Z));
}

#[test]
fn operations_refuse_what_is_no_cube_move() {
    let refused = |operation, args| Move::from_operation(operation, args).expect_err("refused");
    assert!(refused(6, [1, 0, 0, 0]).contains("numbered 0 to 5"));
    assert!(refused(0, [4, 0, 0, 0]).contains("not a direction code"));
    assert!(refused(0, [1, 2, 0, 0]).contains("argument 2 is 2"));
    assert!(refused(2, [1, -1, 0, 0]).contains("perpendicular"));
    assert!(refused(3, [1, 2, 0, 5]).contains("argument 4 is 5"));
    let pivot = Move::from_operation(2, [-3, 1, 0, 0]);
    let expected = Move::Pivot {
        anchor: Dir::MINUS_Z,
        dir: Dir::PLUS_X,
    };
    assert_eq!(pivot, Ok(expected));
    assert_eq!(expected.name(), "pivot");
    assert_eq!(expected.steps(), 1);
}

#[test]
fn every_variant_holds_alone_and_fails_when_one_of_its_cells_changes() {
    for mv in Move::all() {
        for variant in mv.variants() {
            let ground = mover_among(&variant.occupied);
            assert_eq!(ground.check_move(0, &mv), Ok(variant.name), "{mv:?}");
            assert_undone_by_reverse(&ground, 0, &mv);
            for &cell in &variant.empty {
                let blocked = mover_among(&[variant.occupied.clone(), vec![cell]].concat());
                match blocked.check_move(0, &mv) {
                    Err(MoveError::MustBeEmpty { cell: at, .. }) => assert_eq!(at, cell),
                    other => panic!("{mv:?} {} with {cell:?} taken: {other:?}", variant.name),
                }
            }
            for &cell in &variant.occupied {
                let missing = mover_among(&without(&variant.occupied, cell));
                let refusal = missing.check_move(0, &mv);
                assert!(
                    matches!(refusal, Err(MoveError::MustBeOccupied { .. })),
                    "{mv:?} {} without {cell:?}: {refusal:?}",
                    variant.name
                );
            }
        }
    }
}

/// Module m's accepted move `mv` lands where its legs end, and its reverse, accepted from
/// there, brings the lattice back (legs and all).
fn assert_undone_by_reverse(l: &Lattice, m: usize, mv: &Move) {
    let start = l.position(m).expect("a module");
    let destination = plus(start, mv.displacement());
    assert_near(end_of(mv, start.map(f64::from)), destination);
    let back = mv.reverse();
    assert_near(end_of(&back, destination.map(f64::from)), start);
    let mut moved = l.clone();
    assert!(moved.apply_move(m, mv).is_ok());
    assert_eq!(moved.position(m), Some(destination));
    assert!(moved.is_connected(), "{mv:?} from {start:?}");
    let undone = moved.apply_move(m, &back);
    assert!(
        undone.is_ok(),
        "{mv:?} back from {destination:?}: {undone:?}"
    );
    assert_eq!(&moved, l);
}

#[test]
fn moves_refuse_unknown_fixed_and_articulating_modules() {
    // A chain (0,0,0)-(1,0,0)-(2,0,0) along a fixed floor one row below.
    let floor = [[0, 0, -1], [1, 0, -1], [2, 0, -1]];
    let row = [[0, 0, 0], [1, 0, 0], [2, 0, 0]];
    let chain = lattice(&row, &[false; 3]);
    let up = Move::Slide { dir: Dir::PLUS_Z };
    let unknown = chain.check_move(7, &up);
    assert!(matches!(
        unknown,
        Err(MoveError::UnknownModule { module: 7, .. })
    ));
    let middle = Move::Pivot {
        anchor: Dir::PLUS_X,
        dir: Dir::PLUS_Z,
    };
    let articulation = chain.check_move(1, &middle);
    assert!(matches!(
        articulation,
        Err(MoveError::ArticulationPoint { module: 1, .. })
    ));
    let grounded = lattice(
        &[floor.to_vec(), row.to_vec()].concat(),
        &[true, true, true, false, false, false],
    );
    let fixed = grounded.check_move(0, &up);
    assert!(matches!(fixed, Err(MoveError::Fixed { module: 0, .. })));
    // On the floor the middle of the row is no articulation point; it is refused for a cell.
    let lift = Move::Pivot {
        anchor: Dir::MINUS_Z,
        dir: Dir::PLUS_Y,
    };
    let message = grounded.check_move(4, &lift).map_err(|e| e.describe(&name));
    assert_eq!(
        message,
        Err(
            "M4 cannot pivot towards +y with anchor -z: cell (1, 1, -1) must hold a cube but \
             is empty"
                .to_string()
        )
    );
}

#[test]
fn a_move_is_made_only_when_valid() {
    // An L of free cubes: M0 at the origin pivots over M1's edge onto M2's side.
    let mut l = lattice(&[[0, 0, 0], [1, 0, 0], [1, 1, 0]], &[false; 3]);
    let over = Move::Pivot {
        anchor: Dir::PLUS_X,
        dir: Dir::PLUS_Y,
    };
    assert_eq!(l.apply_move(0, &over), Ok("pivot"));
    assert_eq!(l.position(0), Some([0, 1, 0]));
    assert_eq!(l.at([0, 1, 0]), Some(0));
    assert_eq!(l.at([0, 0, 0]), None);
    let before = l.clone();
    assert!(l.apply_move(0, &over).is_err());
    assert_eq!(l, before);
    assert_eq!(l.neighbour(0, Dir::PLUS_X), Some(2));
    assert_eq!(l.neighbour(0, Dir::MINUS_X), None);
}

#[test]
fn lattices_refuse_shared_cells_and_mismatched_lengths() {
    let shared = Lattice::new(vec![[0, 0, 0], [1, 0, 0], [0, 0, 0]], vec![false; 3]);
    let error = shared.expect_err("shared");
    assert_eq!(
        error,
        LatticeError::SharedCell {
            first: 0,
            second: 2,
            cell: [0, 0, 0]
        }
    );
    assert_eq!(
        error.describe(&name),
        "M0 and M2 are both at cell (0, 0, 0)"
    );
    assert!(Lattice::new(vec![[0, 0, 0]], vec![]).is_err());
    let empty = lattice(&[], &[]);
    assert!(empty.is_empty() && empty.is_connected() && empty.articulation_points().is_empty());
}

#[test]
fn the_interior_of_a_chain_articulates_and_a_ring_does_not() {
    let chain: Vec<Cell> = (0..5).map(|x| [x, 0, 0]).collect();
    let points = lattice(&chain, &[false; 5]).articulation_points();
    assert_eq!(points, [false, true, true, true, false]);
    // The 3x3 square without its centre: a ring of eight.
    let ring: Vec<Cell> = (0..3)
        .flat_map(|x| (0..3).map(move |y| [x, y, 0]))
        .filter(|&c| c != [1, 1, 0])
        .collect();
    let ring = lattice(&ring, &[false; 8]);
    assert!(ring.is_connected());
    assert_eq!(ring.articulation_points(), [false; 8]);
    // A chain whose two ends stand on the ground is a ring too.
    let mut ends = [false; 5];
    (ends[0], ends[4]) = (true, true);
    assert_eq!(lattice(&chain, &ends).articulation_points(), [false; 5]);
    assert!(!lattice(&[[0, 0, 0], [2, 0, 0]], &[false; 2]).is_connected());
    assert!(lattice(&[[0, 0, 0], [2, 0, 0]], &[true; 2]).is_connected());
}

#[test]
fn a_chain_of_a_hundred_thousand_modules_is_searched_without_recursion() {
    let n = 100_000;
    let chain: Vec<Cell> = (0..n).map(|x| [x, 0, 0]).collect();
    let points = lattice(&chain, &vec![false; chain.len()]).articulation_points();
    let interior = points.iter().filter(|&&p| p).count();
    assert_eq!(interior, chain.len() - 2);
    assert!(!points[0] && !points[chain.len() - 1]);
}

#[test]
fn monkeys_pass_through_the_middle_cell() {
    let start = [0.0, 0.0, 1.0];
    let monkey = Move::Monkey {
        anchor: Dir::MINUS_Z,
        dir: Dir::PLUS_X,
    };
    let diagonal = Move::DiagonalMonkey {
        anchor: Dir::MINUS_Z,
        dir: Dir::PLUS_X,
    };
    for mv in [monkey, diagonal] {
        let motion = Motion {
            legs: mv.legs(start),
            ..Motion::in_place()
        };
        assert_eq!(mv.steps(), 2);
        assert_near(motion.position_at(start, 0.5), [1, 0, 1]);
    }
    assert_near(end_of(&monkey, start), [2, 0, 1]);
    assert_near(end_of(&diagonal, start), [1, 0, 2]);
}

/// A connected robot of up to 12 cubes in the 4x4x4 box, grown cube by cube from a first one
/// (each new one beside an earlier one), some of them fixed.
fn robots() -> impl Strategy<Value = Lattice> {
    let first = (0..4i32, 0..4i32, 0..4i32);
    let growth = prop::collection::vec((any::<prop::sample::Index>(), 0..6usize), 0..12);
    let fixed = prop::collection::vec(prop::bool::weighted(0.2), 12);
    (first, growth, fixed).prop_map(|((x, y, z), growth, fixed)| {
        let mut cells = vec![[x, y, z]];
        for (parent, dir) in growth {
            let cell = plus(*parent.get(&cells), Dir::ALL[dir].vector());
            if cells.len() < 12 && cell.iter().all(|c| (0..4).contains(c)) && !cells.contains(&cell)
            {
                cells.push(cell);
            }
        }
        let fixed = fixed[..cells.len()].to_vec();
        lattice(&cells, &fixed)
    })
}

/// The robot without module `gone`, connected or not.
fn removed(l: &Lattice, gone: usize) -> Lattice {
    let keep: Vec<usize> = (0..l.len()).filter(|&m| m != gone).collect();
    let positions: Vec<Cell> = keep.iter().filter_map(|&m| l.position(m)).collect();
    let fixed: Vec<bool> = keep.iter().map(|&m| l.is_fixed(m)).collect();
    lattice(&positions, &fixed)
}

proptest! {
    #[test]
    fn accepted_moves_land_where_their_legs_end_and_their_reverse_undoes_them(l in robots()) {
        for m in 0..l.len() {
            for mv in Move::all() {
                if l.check_move(m, &mv).is_ok() {
                    assert_undone_by_reverse(&l, m, &mv);
                }
            }
        }
    }

    #[test]
    fn articulation_points_are_the_modules_whose_removal_disconnects(l in robots()) {
        let points = l.articulation_points();
        prop_assert!(l.is_connected());
        for (m, &point) in points.iter().enumerate() {
            prop_assert_eq!(point, !removed(&l, m).is_connected(), "module {}", m);
        }
    }
}

/// A fixed floor along x from -1 to 4 at z = 0 (modules 0..6), then free cubes.
fn floor_with(free: &[Cell]) -> Lattice {
    let floor = (-1..5).map(|x| [x, 0, 0]);
    let positions: Vec<Cell> = floor.chain(free.iter().copied()).collect();
    let fixed: Vec<bool> = (0..positions.len()).map(|m| m < 6).collect();
    lattice(&positions, &fixed)
}

fn slide(dir: Dir) -> Move {
    Move::Slide { dir }
}

#[test]
fn the_empty_set_and_a_valid_set_pass() {
    let mut l = floor_with(&[[0, 0, 1], [3, 0, 1]]);
    assert_eq!(l.check_set(&[]), Ok(()));
    let apart = [(6, slide(Dir::MINUS_X)), (7, slide(Dir::PLUS_X))];
    assert_eq!(l.apply_set(&apart), Ok(()));
    assert_eq!(l.position(6), Some([-1, 0, 1]));
    assert_eq!(l.position(7), Some([4, 0, 1]));
}

#[test]
fn a_module_moving_twice_is_refused() {
    let l = floor_with(&[[0, 0, 1]]);
    let twice = [(6, slide(Dir::PLUS_X)), (6, slide(Dir::MINUS_X))];
    assert_eq!(l.check_set(&twice), Err(SetError::Twice { module: 6 }));
}

#[test]
fn a_move_invalid_alone_is_refused_with_its_place() {
    let mut l = floor_with(&[[0, 0, 1]]);
    let before = l.clone();
    let set = [(6, slide(Dir::PLUS_X)), (0, slide(Dir::PLUS_Z))];
    let refusal = l.apply_set(&set);
    assert!(matches!(
        refusal,
        Err(SetError::Move {
            index: 1,
            error: MoveError::Fixed { .. }
        })
    ));
    assert_eq!(l, before);
}

#[test]
fn two_movers_claiming_one_cell_are_refused() {
    let l = floor_with(&[[0, 0, 1], [2, 0, 1]]);
    let meet = [(6, slide(Dir::PLUS_X)), (7, slide(Dir::MINUS_X))];
    let refusal = l.check_set(&meet);
    assert_eq!(
        refusal,
        Err(SetError::ClaimedTwice {
            cell: [1, 0, 1],
            movers: [6, 7]
        })
    );
    let message = refusal.map_err(|e| e.describe(&name));
    assert_eq!(
        message,
        Err("M6 and M7 both claim cell (1, 0, 1)".to_string())
    );
}

#[test]
fn a_mover_standing_on_another_mover_is_refused() {
    // M8 on top of M7 slides -x over M7 and M6, while M6 slides away along the floor.
    let l = floor_with(&[[0, 0, 1], [1, 0, 1], [1, 0, 2]]);
    let set = [(8, slide(Dir::MINUS_X)), (6, slide(Dir::MINUS_X))];
    assert!(l.check_move(8, &set[0].1).is_ok() && l.check_move(6, &set[1].1).is_ok());
    let refusal = l.check_set(&set);
    assert_eq!(
        refusal,
        Err(SetError::Supports {
            mover: 8,
            support: 6,
            cell: [0, 0, 1]
        })
    );
    let message = refusal.map_err(|e| e.describe(&name));
    let expected = "M8 needs M6 at cell (0, 0, 1) as a support, but M6 moves in the same set";
    assert_eq!(message, Err(expected.to_string()));
}

#[test]
fn movers_leaving_the_stay_put_modules_apart_are_refused() {
    // A ring of six in the plane z = 0 with two more cubes above its right column; the two
    // cubes of the middle column both slide up, each fine alone, and cut the ring in two.
    let ring = [
        [0, 0, 0],
        [1, 0, 0],
        [2, 0, 0],
        [2, 1, 0],
        [1, 1, 0],
        [0, 1, 0],
    ];
    let above = [[2, 0, 1], [2, 1, 1]];
    let l = lattice(&[ring.to_vec(), above.to_vec()].concat(), &[false; 8]);
    let up = Move::Slide { dir: Dir::PLUS_Z };
    assert!(l.check_move(1, &up).is_ok() && l.check_move(4, &up).is_ok());
    let refusal = l.check_set(&[(1, up), (4, up)]);
    assert_eq!(refusal, Err(SetError::StayPutApart { first: 0, apart: 2 }));
}

#[test]
fn a_mover_claiming_a_cell_a_monkey_still_holds_is_refused() {
    // M2 monkeys from (0,0,1) over the gap to (2,0,1); M3 waits on fixed (3,0,0) at (3,0,1).
    let positions = [[0, 0, 0], [2, 0, 0], [0, 0, 1], [3, 0, 0], [3, 0, 1]];
    let mut l = lattice(&positions, &[true, true, false, true, false]);
    let monkey = Move::Monkey {
        anchor: Dir::MINUS_Z,
        dir: Dir::PLUS_X,
    };
    let underway: Vec<Underway> = l.underway(2, &monkey).into_iter().collect();
    let claim: BTreeSet<Cell> = underway[0].claim.iter().copied().collect();
    assert!(claim.contains(&[1, 0, 1]) && claim.contains(&[2, 0, 1]));
    assert_eq!(underway[0].hinge, [2, 0, 0]);
    assert_eq!(l.apply_set(&[(2, monkey)]), Ok(()));
    // Landed (as dynarole makes it), M3 could pivot 180° over it to (2,0,2); mid-air, not.
    let over = Move::Pivot180 {
        anchor: Dir::MINUS_X,
        dir: Dir::PLUS_Z,
    };
    assert_eq!(l.check_set(&[(4, over)]), Ok(()));
    let refusal = l.check_set_alongside(&[(4, over)], &underway);
    assert_eq!(
        refusal,
        Err(SetError::Reserved {
            cell: [2, 0, 2],
            mover: 4,
            underway: 2
        })
    );
    // The monkey under way alone leaves the rest connected.
    assert_eq!(l.check_set_alongside(&[], &underway), Ok(()));
}
