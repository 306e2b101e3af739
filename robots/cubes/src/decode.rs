//! A cube scenario's move lines as moves: each `id, anchorDirCode, dx, dy, dz` line decoded
//! from the current occupancy (the domain notes' mapping and corrections), monkeys found across
//! two sets, every set checked by the planners' parallel-move rules and made in order.

use crate::lattice::{format_cell, Cell, Dir, Lattice, Move, SetError, Structure, Underway};
use std::collections::BTreeSet;
use std::fmt;

/// One move line of a scenario, with its module already mapped to an index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LineMove {
    pub line: usize,
    pub module: usize,
    pub code: i64,
    pub d: Cell,
}

/// A move of the plan, with the line it was read from (a monkey: its first line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlannedMove {
    pub line: usize,
    pub module: usize,
    pub mv: Move,
}

/// Why a plan is refused: the line and a sentence (names through `name`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodeError {
    pub line: usize,
    pub message: String,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for DecodeError {}

/// The anchor direction of a pivot code's one digit: +x=1, +y=2, +z=3, -x=4, -y=5, -z=6.
pub fn anchor_of_digit(code: i64) -> Option<Dir> {
    let place = usize::try_from(code.checked_sub(1)?).ok()?;
    ANCHOR_DIGITS.get(place).copied()
}

/// The anchor directions of a pivot's code, digit 1 first: the one table the reader and the
/// writer (`export.rs`) share.
pub const ANCHOR_DIGITS: [Dir; 6] = [
    Dir::PLUS_X,
    Dir::PLUS_Y,
    Dir::PLUS_Z,
    Dir::MINUS_X,
    Dir::MINUS_Y,
    Dir::MINUS_Z,
];

/// The digit of an anchor direction in a pivot's code.
pub fn digit_of_anchor(dir: Dir) -> i64 {
    let place = ANCHOR_DIGITS.iter().position(|d| *d == dir).unwrap_or(0);
    place as i64 + 1
}

/// The cube move a line's code and displacement name, regardless of the occupancy, or why
/// they name none (the part of a sentence after "is not a cube move:").
pub fn decode_code(code: i64, d: Cell) -> Result<Move, String> {
    if code >= 1000 {
        return Err(format!(
            "anchor code {code} is a catom's (1000 and above), and this robot is made of cubes"
        ));
    }
    if code >= 10 {
        return Err(format!(
            "anchor code {code} has several digits, as a rhombic dodecahedron's does, and a cube's has one"
        ));
    }
    let steps = unit_steps(d)?;
    match (code, steps.as_slice()) {
        // A straight slide's code may name any axis, or none (correction 6).
        (..=0, [dir]) => Ok(Move::Slide { dir: *dir }),
        (0, _) => {
            Err("anchor code 0 is a straight slide of one step, and this move has two".into())
        }
        (..=-1, [u, v]) => corner_slide(code, *u, *v),
        (_, _) => {
            let anchor = anchor_of_digit(code).ok_or_else(|| {
                format!("anchor code {code} is no anchor direction (those are 1 to 6)")
            })?;
            pivot(anchor, &steps)
        }
    }
}

/// The unit steps of `d` along x, y, z in that order: one, or two perpendicular ones.
fn unit_steps(d: Cell) -> Result<Vec<Dir>, String> {
    if d.iter().any(|c| c.abs() > 1) {
        return Err(format!(
            "every component of a cube move is -1, 0 or 1, and {} has another",
            format_cell(d)
        ));
    }
    let steps: Vec<Dir> = (0..3)
        .filter(|&k| d[k] != 0)
        .filter_map(|k| {
            let mut unit = [0; 3];
            unit[k] = d[k];
            Dir::from_vector(unit)
        })
        .collect();
    match steps.len() {
        0 => Err("it does not move".into()),
        1 | 2 => Ok(steps),
        _ => Err("a cube moves by one step or two perpendicular ones, and this is three".into()),
    }
}

/// A corner slide whose first leg runs along the axis `-code` names (1 = x, 2 = y, 3 = z).
fn corner_slide(code: i64, u: Dir, v: Dir) -> Result<Move, String> {
    let axis = -code;
    if axis > 3 {
        return Err(format!(
            "anchor code {code} names no axis for a corner slide's first leg (those are -1 to -3)"
        ));
    }
    let along = |dir: Dir| dir.code().abs() == axis;
    match (along(u), along(v)) {
        (true, _) => Ok(Move::CornerSlide {
            first: u,
            second: v,
        }),
        (_, true) => Ok(Move::CornerSlide {
            first: v,
            second: u,
        }),
        _ => Err(format!(
            "anchor code {code} puts the corner slide's first leg along the {} axis, which the move does not step along",
            ["x", "y", "z"][usize::try_from(axis - 1).unwrap_or(0)]
        )),
    }
}

/// A 90° pivot (one step, perpendicular to the anchor) or a 180° pivot (a step `t` and the
/// anchor's own step).
fn pivot(anchor: Dir, steps: &[Dir]) -> Result<Move, String> {
    match steps {
        [dir] if dir.is_perpendicular(anchor) => Ok(Move::Pivot { anchor, dir: *dir }),
        [_] => Err(format!(
            "a pivot moves across its anchor direction {anchor}, and this move is along its axis"
        )),
        [u, v] if *v == anchor => Ok(Move::Pivot180 { anchor, dir: *u }),
        [u, v] if *u == anchor => Ok(Move::Pivot180 { anchor, dir: *v }),
        _ => Err(format!(
            "a two-step pivot ends one step towards its anchor direction {anchor}, and this move has no such step"
        )),
    }
}

/// The move of one line from `lattice` (one-line moves only), or why not, modules named by
/// `name(index)`.
pub fn decode_line(
    lattice: &Lattice,
    line: &LineMove,
    name: &dyn Fn(usize) -> String,
) -> Result<Move, String> {
    if line.module >= lattice.len() {
        return Err(unknown_module(line.module));
    }
    decode_line_in(lattice, &lattice.structure(), line, name)
}

fn unknown_module(module: usize) -> String {
    format!("the line moves module index {module}, which the robot does not have")
}

fn decode_line_in(
    lattice: &Lattice,
    structure: &Structure,
    line: &LineMove,
    name: &dyn Fn(usize) -> String,
) -> Result<Move, String> {
    let what = || {
        format!(
            "{}'s move {} with anchor code {}",
            name(line.module),
            format_cell(line.d),
            line.code
        )
    };
    let mv = decode_code(line.code, line.d)
        .map_err(|why| format!("{} is not a cube move: {why}", what()))?;
    lattice
        .check_move_in(structure, line.module, &mv)
        .map_err(|error| {
            format!(
                "{} is not a cube move from where it is: {}",
                what(),
                error.reason(name)
            )
        })?;
    Ok(mv)
}

/// A monkey begun in one set, whose second line is in the next.
struct Begun {
    underway: Underway,
    /// The place of its second line in the next set.
    second_line: usize,
}

/// What one set decodes to: its moves as dynarole makes them, and the monkeys it begins.
struct SetMoves {
    moves: Vec<PlannedMove>,
    begun: Vec<Begun>,
}

/// Every set decoded, checked and made in order, from `lattice`; returns the sets as dynarole
/// executes them (a monkey whole in the set it starts in; a set left empty by that is
/// dropped) and the final lattice.
///
/// The planners' parallel rules hold a monkey in the air during the set after the one it
/// starts in. Rather than a variant of the rules, one wrapper over them serves both sets,
/// `Lattice::check_set_alongside`: the set a monkey starts in checks it as any mover (its claim
/// is its whole move's, it is no module that stays put); the next set is checked alongside it,
/// which keeps its claim reserved, its hinge still, and leaves it out of the modules that stay
/// put. The lattice between the two has it landed, as dynarole makes it whole; each set is then
/// made with `apply_set`, whose plain rules the stricter check implies.
pub fn decode_sets(
    lattice: Lattice,
    sets: &[Vec<LineMove>],
    name: &dyn Fn(usize) -> String,
) -> Result<(Vec<Vec<PlannedMove>>, Lattice), DecodeError> {
    refuse_unknown_modules(&lattice, sets)?;
    let mut lattice = lattice;
    let mut planned = Vec::new();
    let mut begun: Vec<Begun> = Vec::new();
    for (k, set) in sets.iter().enumerate() {
        let next = sets.get(k + 1).map(Vec::as_slice).unwrap_or(&[]);
        // One search for articulation points serves the set's lines and its parallel rules.
        let structure = lattice.structure();
        let decoded = decode_set(&lattice, &structure, set, next, &begun, name)?;
        let moves: Vec<(usize, Move)> = decoded.moves.iter().map(|p| (p.module, p.mv)).collect();
        let underway: Vec<Underway> = begun.into_iter().map(|b| b.underway).collect();
        let first_line = set.first().map_or(0, |l| l.line);
        lattice
            .check_set_in(&structure, &moves, &underway)
            .map_err(|error| set_refusal(&error, &decoded.moves, first_line, name))?;
        lattice.apply_set(&moves).map_err(|error| DecodeError {
            line: first_line,
            message: error.describe(name),
        })?;
        begun = decoded.begun;
        if !decoded.moves.is_empty() {
            planned.push(decoded.moves);
        }
    }
    Ok((planned, lattice))
}

/// Every line's module must be one of the lattice's, so that `name` is only asked of those.
fn refuse_unknown_modules(lattice: &Lattice, sets: &[Vec<LineMove>]) -> Result<(), DecodeError> {
    match sets.iter().flatten().find(|l| l.module >= lattice.len()) {
        Some(l) => Err(DecodeError {
            line: l.line,
            message: unknown_module(l.module),
        }),
        None => Ok(()),
    }
}

/// The lines of one set as moves from `lattice`, skipping the second lines of the monkeys
/// `begun` in the set before.
fn decode_set(
    lattice: &Lattice,
    structure: &Structure,
    set: &[LineMove],
    next: &[LineMove],
    begun: &[Begun],
    name: &dyn Fn(usize) -> String,
) -> Result<SetMoves, DecodeError> {
    let second_lines: BTreeSet<usize> = begun.iter().map(|b| b.second_line).collect();
    let mut seen: BTreeSet<usize> = begun.iter().map(|b| b.underway.module).collect();
    let mut decoded = SetMoves {
        moves: Vec::new(),
        begun: Vec::new(),
    };
    for (place, line) in set.iter().enumerate() {
        if second_lines.contains(&place) {
            continue;
        }
        if !seen.insert(line.module) {
            return Err(DecodeError {
                line: line.line,
                message: format!("{} moves twice in one set", name(line.module)),
            });
        }
        let mv = match decode_line_in(lattice, structure, line, name) {
            Ok(mv) => mv,
            Err(refusal) => {
                let (monkey, mv) = begin_monkey(lattice, structure, line, next, name, refusal)?;
                decoded.begun.push(monkey);
                mv
            }
        };
        decoded.moves.push(PlannedMove {
            line: line.line,
            module: line.module,
            mv,
        });
    }
    Ok(decoded)
}

/// A line that makes no one-line move may begin a monkey finished by the same module's line in
/// the next set (correction 5); `refusal` is the one-line move's, reported when it does not.
fn begin_monkey(
    lattice: &Lattice,
    structure: &Structure,
    line: &LineMove,
    next: &[LineMove],
    name: &dyn Fn(usize) -> String,
    refusal: String,
) -> Result<(Begun, Move), DecodeError> {
    let refuse = |message: String| DecodeError {
        line: line.line,
        message,
    };
    let Some((second_line, mv)) = monkey_of(line, next) else {
        return Err(refuse(refusal));
    };
    if let Err(error) = lattice.check_move_in(structure, line.module, &mv) {
        return Err(refuse(format!(
            "{refusal}; nor does it begin a monkey move with line {}: {}",
            next[second_line].line,
            error.reason(name)
        )));
    }
    let underway = lattice
        .underway(line.module, &mv)
        .ok_or_else(|| refuse(format!("{refusal}; {} is no monkey move", mv.phrase())))?;
    let begun = Begun {
        underway,
        second_line,
    };
    Ok((begun, mv))
}

/// The monkey a line (a pivot code, one step `t` across the anchor `a`) begins with its
/// module's first line of the next set: that line steps `t` again (a monkey, `2t`) or `-a` (a
/// diagonal monkey, `t - a`), with any one-digit code; and the place of that line.
fn monkey_of(line: &LineMove, next: &[LineMove]) -> Option<(usize, Move)> {
    let anchor = anchor_of_digit(line.code)?;
    let dir = Dir::from_vector(line.d).filter(|t| t.is_perpendicular(anchor))?;
    let (place, second) = next
        .iter()
        .enumerate()
        .find(|(_, l)| l.module == line.module)?;
    anchor_of_digit(second.code)?;
    let mv = if second.d == dir.vector() {
        Move::Monkey { anchor, dir }
    } else if second.d == anchor.reversed().vector() {
        Move::DiagonalMonkey { anchor, dir }
    } else {
        return None;
    };
    Some((place, mv))
}

/// A set's refusal at the line of the mover it blames (the later of two that clash), or at the
/// set's first line when it blames the set as a whole.
fn set_refusal(
    error: &SetError,
    moves: &[PlannedMove],
    first_line: usize,
    name: &dyn Fn(usize) -> String,
) -> DecodeError {
    let line_of = |m: usize| moves.iter().find(|p| p.module == m).map(|p| p.line);
    let line = match error {
        SetError::Twice { module } => line_of(*module),
        SetError::Move { index, .. } => moves.get(*index).map(|p| p.line),
        SetError::ClaimedTwice { movers, .. } => line_of(movers[0]).max(line_of(movers[1])),
        SetError::Reserved { mover, .. } | SetError::Enters { mover, .. } => line_of(*mover),
        // A monkey under way has no line in this set: blame the support that moves.
        SetError::Supports { mover, support, .. } => line_of(*mover).or(line_of(*support)),
        SetError::StayPutApart { .. } => None,
    };
    DecodeError {
        line: line.unwrap_or(first_line),
        message: error.describe(name),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(m: usize) -> String {
        format!("M{m}")
    }

    /// A fixed floor of `width` cubes along x at z = 0 (modules 0..width), then `free` cubes.
    fn on_floor(width: i32, free: &[Cell]) -> Lattice {
        let floor = (0..width).map(|x| [x, 0, 0]);
        let positions: Vec<Cell> = floor.chain(free.iter().copied()).collect();
        let fixed = (0..positions.len())
            .map(|m| m < usize::try_from(width).unwrap_or(0))
            .collect();
        Lattice::new(positions, fixed).expect("a valid lattice")
    }

    fn line(line: usize, module: usize, code: i64, d: Cell) -> LineMove {
        LineMove {
            line,
            module,
            code,
            d,
        }
    }

    #[test]
    fn each_code_kind_decodes() {
        let slide = |dir| Move::Slide { dir };
        assert_eq!(decode_code(0, [1, 0, 0]), Ok(slide(Dir::PLUS_X)));
        // Correction 6: a negative code's axis need not match a straight slide.
        assert_eq!(decode_code(-1, [0, 0, -1]), Ok(slide(Dir::MINUS_Z)));
        assert_eq!(
            decode_code(-2, [1, -1, 0]),
            Ok(Move::CornerSlide {
                first: Dir::MINUS_Y,
                second: Dir::PLUS_X
            })
        );
        assert_eq!(
            decode_code(6, [0, 1, 0]),
            Ok(Move::Pivot {
                anchor: Dir::MINUS_Z,
                dir: Dir::PLUS_Y
            })
        );
        assert_eq!(
            decode_code(4, [-1, 1, 0]),
            Ok(Move::Pivot180 {
                anchor: Dir::MINUS_X,
                dir: Dir::PLUS_Y
            })
        );
    }

    #[test]
    fn codes_and_displacements_of_no_cube_move_are_refused() {
        let refused = |code, d| decode_code(code, d).expect_err("refused");
        assert!(refused(-3, [1, 1, 0]).contains("along the z axis"));
        assert!(refused(-4, [1, 1, 0]).contains("-1 to -3"));
        assert!(refused(0, [1, 1, 0]).contains("two"));
        assert!(refused(56, [0, 1, 1]).contains("rhombic dodecahedron"));
        assert!(refused(1001, [1, 1, 0]).contains("catom"));
        assert!(refused(7, [1, 0, 0]).contains("1 to 6"));
        assert!(refused(1, [1, 0, 0]).contains("along its axis"));
        assert!(refused(1, [0, 1, 1]).contains("no such step"));
        assert!(refused(0, [0, 0, 0]).contains("does not move"));
        assert!(refused(0, [2, 0, 0]).contains("-1, 0 or 1"));
        assert!(refused(0, [1, 1, 1]).contains("three"));
    }

    #[test]
    fn a_line_is_checked_against_the_occupancy() {
        // Floor x = 0..3; M3 at (0,0,1) slides +x along it; M4 at (1,0,1) is in the way.
        let lattice = on_floor(3, &[[0, 0, 1], [1, 0, 1]]);
        let blocked = decode_line(&lattice, &line(9, 3, 0, [1, 0, 0]), &name);
        assert_eq!(
            blocked,
            Err(
                "M3's move (1, 0, 0) with anchor code 0 is not a cube move from where it is: \
                 cell (1, 0, 1) must be empty but M4 is there"
                    .to_string()
            )
        );
        let up = decode_line(&lattice, &line(9, 4, 0, [1, 0, 0]), &name);
        assert_eq!(up, Ok(Move::Slide { dir: Dir::PLUS_X }));
        let unknown = decode_line(&lattice, &line(9, 7, 0, [1, 0, 0]), &name);
        assert!(unknown.expect_err("refused").contains("index 7"));
    }

    /// Fixed cubes at (0,0,0) and (2,0,0) with a gap between, M2 on the first at (0,0,1):
    /// it cannot pivot to (1,0,1), but it can monkey over the gap to (2,0,1).
    fn gap() -> Lattice {
        let positions = vec![[0, 0, 0], [2, 0, 0], [0, 0, 1]];
        Lattice::new(positions, vec![true, true, false]).expect("valid")
    }

    #[test]
    fn a_monkey_across_two_sets_is_one_move() {
        let sets = vec![
            vec![line(10, 2, 6, [1, 0, 0])],
            vec![line(11, 2, 6, [1, 0, 0])],
        ];
        let (planned, end) = decode_sets(gap(), &sets, &name).expect("a monkey");
        let monkey = Move::Monkey {
            anchor: Dir::MINUS_Z,
            dir: Dir::PLUS_X,
        };
        let expected = PlannedMove {
            line: 10,
            module: 2,
            mv: monkey,
        };
        // The second set held only the monkey's second line, so it is dropped.
        assert_eq!(planned, vec![vec![expected]]);
        assert_eq!(end.position(2), Some([2, 0, 1]));
    }

    #[test]
    fn a_diagonal_monkey_across_two_sets_is_one_move() {
        // M2 at (0,0,1) above fixed (0,0,0) turns over (1,0,0)'s empty top edge to (1,0,1),
        // then up about the edge of fixed (2,0,2) to (1,0,2): t = +x, a = -z, t - a.
        let positions = vec![[0, 0, 0], [2, 0, 2], [0, 0, 1]];
        let lattice = Lattice::new(positions, vec![true, true, false]).expect("valid");
        let sets = vec![
            vec![line(20, 2, 6, [1, 0, 0])],
            vec![line(21, 2, 1, [0, 0, 1])],
        ];
        let (planned, end) = decode_sets(lattice, &sets, &name).expect("a diagonal monkey");
        let diagonal = Move::DiagonalMonkey {
            anchor: Dir::MINUS_Z,
            dir: Dir::PLUS_X,
        };
        let expected = PlannedMove {
            line: 20,
            module: 2,
            mv: diagonal,
        };
        assert_eq!(planned, vec![vec![expected]]);
        assert_eq!(end.position(2), Some([1, 0, 2]));
    }

    #[test]
    fn a_monkey_without_its_second_line_is_refused_at_its_line() {
        let sets = vec![
            vec![line(10, 2, 6, [1, 0, 0])],
            vec![line(11, 2, 0, [0, 0, 1])],
        ];
        let error = decode_sets(gap(), &sets, &name).expect_err("no monkey");
        assert_eq!(error.line, 10);
        let expected = "M2's move (1, 0, 0) with anchor code 6 is not a cube move from where it \
                        is: cell (1, 0, 0) must hold a cube but is empty";
        assert_eq!(error.message, expected);
    }

    /// The gap, with a fixed (3,0,0) and M3 on it at (3,0,1), beside the monkey's landing.
    fn gap_with_neighbour(hinge_fixed: bool) -> Lattice {
        let positions = vec![
            [0, 0, 0],
            [2, 0, 0],
            [0, 0, 1],
            [3, 0, 0],
            [3, 0, 1],
            [3, -1, 0],
        ];
        let fixed = vec![true, hinge_fixed, false, true, false, true];
        Lattice::new(positions, fixed).expect("valid")
    }

    #[test]
    fn a_mover_claiming_a_cell_of_a_monkey_in_the_air_is_refused() {
        // In the second set M4 pivots 180° over the landed monkey to (2,0,2), which the
        // monkey still holds in the planners' semantics (it is only half-way there).
        let sets = vec![
            vec![line(30, 2, 6, [1, 0, 0])],
            vec![line(31, 2, 6, [1, 0, 0]), line(32, 4, 4, [-1, 0, 1])],
        ];
        let error = decode_sets(gap_with_neighbour(true), &sets, &name).expect_err("refused");
        let expected = DecodeError {
            line: 32,
            message: "M4 claims cell (2, 0, 2), which M2's monkey move still holds until it lands"
                .into(),
        };
        assert_eq!(error, expected);
    }

    #[test]
    fn the_hinge_of_a_monkey_in_the_air_stays_put() {
        // M1 at (2,0,0), not fixed, is the edge the monkey's second pivot turns about; it
        // slides away along the fixed (3,0,0) and (3,-1,0) in the monkey's second set.
        let sets = vec![
            vec![line(40, 2, 6, [1, 0, 0])],
            vec![line(41, 2, 6, [1, 0, 0]), line(42, 1, 0, [0, -1, 0])],
        ];
        let error = decode_sets(gap_with_neighbour(false), &sets, &name).expect_err("refused");
        let expected = DecodeError {
            line: 42,
            message: "M2 needs M1 at cell (2, 0, 0) as a support, but M1 moves in the same set"
                .into(),
        };
        assert_eq!(error, expected);
        // The same slide a set later, once the monkey has landed, is fine.
        let later = vec![
            sets[0].clone(),
            vec![sets[1][0].clone()],
            vec![sets[1][1].clone()],
        ];
        let (planned, end) = decode_sets(gap_with_neighbour(false), &later, &name).expect("fine");
        assert_eq!(planned.len(), 2);
        assert_eq!(end.position(1), Some([2, -1, 0]));
    }

    #[test]
    fn a_second_line_of_one_module_in_a_set_is_refused_at_that_line() {
        let lattice = on_floor(3, &[[0, 0, 1]]);
        let sets = vec![vec![line(5, 3, 0, [1, 0, 0]), line(6, 3, 0, [1, 0, 0])]];
        let error = decode_sets(lattice, &sets, &name).expect_err("twice");
        assert_eq!(
            error,
            DecodeError {
                line: 6,
                message: "M3 moves twice in one set".into()
            }
        );
    }

    #[test]
    fn two_lines_claiming_one_cell_are_refused_at_the_later() {
        let lattice = on_floor(3, &[[0, 0, 1], [2, 0, 1]]);
        let sets = vec![vec![line(5, 3, 0, [1, 0, 0]), line(8, 4, -1, [-1, 0, 0])]];
        let error = decode_sets(lattice, &sets, &name).expect_err("a clash");
        let expected = DecodeError {
            line: 8,
            message: "M3 and M4 both claim cell (1, 0, 1)".into(),
        };
        assert_eq!(error, expected);
        assert_eq!(
            error.to_string(),
            "line 8: M3 and M4 both claim cell (1, 0, 1)"
        );
    }

    #[test]
    fn sets_are_made_in_order_and_refusals_name_their_line() {
        let lattice = on_floor(4, &[[0, 0, 1]]);
        let sets = vec![
            vec![line(5, 4, 0, [1, 0, 0])],
            vec![line(7, 4, -1, [1, 0, 0])],
            vec![line(9, 4, 0, [1, 0, 0])],
        ];
        let (planned, end) = decode_sets(lattice.clone(), &sets, &name).expect("three slides");
        assert_eq!(planned.len(), 3);
        assert_eq!(end.position(4), Some([3, 0, 1]));
        let too_far = [sets.clone(), vec![vec![line(11, 4, 0, [1, 0, 0])]]].concat();
        let error = decode_sets(lattice, &too_far, &name).expect_err("off the floor");
        assert_eq!(error.line, 11);
        assert!(error.message.contains("cell (4, 0, 0) must hold a cube"));
    }
}
