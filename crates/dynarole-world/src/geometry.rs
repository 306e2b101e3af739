//! Exact lattice geometry: integer vectors, the 24 rotations of the cube, and the continuous
//! sweep distance used by the collision checks.

use std::fmt;

/// An integer vector (lattice units of the robot in question).
pub type Vec3 = [i32; 3];

/// Largest absolute coordinate accepted from input; keeps every later sum and rotation far from
/// `i32` overflow.
pub const MAX_COORDINATE: i32 = 1 << 20;

/// Component-wise sum.
pub fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Component-wise difference `a - b`.
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Multiplies every component by `k`.
pub fn scale(a: Vec3, k: i32) -> Vec3 {
    [a[0] * k, a[1] * k, a[2] * k]
}

/// True when every coordinate is within [`MAX_COORDINATE`].
pub fn within_bounds(a: Vec3) -> bool {
    // `unsigned_abs`: i32::MIN, which a file can give, has no `abs()`.
    a.iter()
        .all(|c| c.unsigned_abs() <= MAX_COORDINATE.unsigned_abs())
}

/// A proper rotation that maps the integer lattice onto itself: a signed permutation matrix with
/// determinant +1. Only the 24 such matrices can be constructed, so a pose built from them never
/// leaves the lattice.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct Rotation {
    /// Row-major entries, each -1, 0 or 1.
    rows: [[i8; 3]; 3],
}

impl Rotation {
    /// The identity rotation.
    pub const IDENTITY: Rotation = Rotation {
        rows: [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    };

    /// Builds a rotation from rows known to form a signed permutation with determinant +1; only
    /// for the crate's constant tables (a unit test checks each of them).
    pub const fn from_rows_unchecked(rows: [[i8; 3]; 3]) -> Rotation {
        Rotation { rows }
    }

    /// Builds the rotation whose columns (images of local x, y, z) are the given vectors, if they
    /// are signed unit axes forming a right-handed frame.
    pub fn from_columns(x: Vec3, y: Vec3, z: Vec3) -> Option<Rotation> {
        let columns = [x, y, z];
        if !columns.iter().all(|c| is_unit_axis(*c)) || cross(x, y) != z {
            return None;
        }
        let mut rows = [[0i8; 3]; 3];
        for (col, v) in columns.iter().enumerate() {
            for (row, entry) in v.iter().enumerate() {
                // Entries are -1, 0 or 1 (checked by is_unit_axis), so the conversion is exact.
                rows[row][col] = i8::try_from(*entry).unwrap_or(0);
            }
        }
        Some(Rotation { rows })
    }

    /// All 24 lattice rotations, in a fixed order (identity first).
    pub fn all() -> Vec<Rotation> {
        let axes: [Vec3; 6] = [
            [1, 0, 0],
            [0, 1, 0],
            [0, 0, 1],
            [-1, 0, 0],
            [0, -1, 0],
            [0, 0, -1],
        ];
        let mut out = Vec::with_capacity(24);
        for x in axes {
            for y in axes {
                if let Some(r) = Rotation::from_columns(x, y, cross(x, y)) {
                    out.push(r);
                }
            }
        }
        out.sort_by_key(|r| *r != Rotation::IDENTITY);
        out
    }

    /// `quarters` quarter turns (right-handed, positive = counter-clockwise seen from the tip of
    /// `axis`) about a signed unit axis; `None` if `axis` is not one.
    pub fn about_axis(axis: Vec3, quarters: i32) -> Option<Rotation> {
        if !is_unit_axis(axis) {
            return None;
        }
        // One quarter turn about unit a maps v to (a.v) a + a x v.
        let quarter = |v: Vec3| add(scale(axis, dot(axis, v)), cross(axis, v));
        let mut columns = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
        for column in columns.iter_mut() {
            for _ in 0..quarters.rem_euclid(4) {
                *column = quarter(*column);
            }
        }
        Rotation::from_columns(columns[0], columns[1], columns[2])
    }

    /// The image of lattice vector `v`.
    pub fn apply(&self, v: Vec3) -> Vec3 {
        let mut out = [0; 3];
        for (row, o) in self.rows.iter().zip(out.iter_mut()) {
            *o = row
                .iter()
                .zip(v.iter())
                .map(|(r, x)| i32::from(*r) * x)
                .sum();
        }
        out
    }

    /// The composition `self * other` (apply `other` first).
    pub fn compose(&self, other: &Rotation) -> Rotation {
        let mut rows = [[0i8; 3]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                *entry = (0..3).map(|k| self.rows[i][k] * other.rows[k][j]).sum();
            }
        }
        Rotation { rows }
    }

    /// The inverse rotation (the transpose, since the matrix is orthogonal).
    pub fn inverse(&self) -> Rotation {
        let mut rows = [[0i8; 3]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                *entry = self.rows[j][i];
            }
        }
        Rotation { rows }
    }

    /// Column `index` (0 = image of local x, 1 = y, 2 = z); `index` is taken modulo 3.
    pub fn column(&self, index: usize) -> Vec3 {
        let j = index % 3;
        [
            i32::from(self.rows[0][j]),
            i32::from(self.rows[1][j]),
            i32::from(self.rows[2][j]),
        ]
    }

    /// The matrix as rows of integers.
    pub fn rows(&self) -> [[i32; 3]; 3] {
        self.rows.map(|row| row.map(i32::from))
    }
}

impl fmt::Display for Rotation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Written as the images of x, y and z, which reads better than a matrix in one line.
        write!(
            f,
            "x->{} y->{} z->{}",
            axis_name(self.column(0)),
            axis_name(self.column(1)),
            axis_name(self.column(2))
        )
    }
}

/// `+x`, `-z`, ... for a signed unit axis; the vector itself otherwise.
pub fn axis_name(v: Vec3) -> String {
    let names = ["x", "y", "z"];
    match v.iter().position(|c| *c != 0) {
        Some(i) if is_unit_axis(v) => format!("{}{}", if v[i] > 0 { '+' } else { '-' }, names[i]),
        _ => format!("{v:?}"),
    }
}

/// True for the six vectors (+-1, 0, 0), (0, +-1, 0), (0, 0, +-1).
pub fn is_unit_axis(v: Vec3) -> bool {
    // No `abs()` or sum: they overflow on the extreme values a file can give.
    v.iter().all(|c| (-1..=1).contains(c)) && v.iter().filter(|c| **c != 0).count() == 1
}

/// Dot product.
pub fn dot(a: Vec3, b: Vec3) -> i32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product.
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The closest approach found while sweeping a set of points about an axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepApproach {
    /// Smallest centre-to-centre distance, in the unit of the input points.
    pub distance: f64,
    /// Index of the moving point.
    pub moving: usize,
    /// Index of the still point.
    pub still: usize,
    /// How far into the turn it happens, in degrees (absolute).
    pub angle_deg: f64,
}

/// Closest approach between `moving` points turned continuously by `angle_deg` (signed,
/// right-handed about the unit `axis` through `pivot`) and `still` points.
///
/// The distance is minimised in closed form rather than by sampling: the squared distance is
/// `K - 2 (alpha cos t + beta sin t)`, whose extremum is known exactly, so minima that fall
/// between samples (a lattice module's occur about 27 and 63 degrees into a quarter turn) are never
/// missed.
pub fn sweep_closest_approach(
    pivot: [f64; 3],
    axis: [f64; 3],
    angle_deg: f64,
    moving: &[[f64; 3]],
    still: &[[f64; 3]],
) -> Option<SweepApproach> {
    let a = axis;
    let total = angle_deg.abs().to_radians();
    // Turning by a negative angle about a is the same as a positive one about -a.
    let a = if angle_deg < 0.0 { a.map(|c| -c) } else { a };
    let mut best: Option<SweepApproach> = None;
    for (mi, m) in moving.iter().enumerate() {
        for (si, s) in still.iter().enumerate() {
            // A lower bound first (the distance between the full circle and the point, in
            // cylindrical coordinates about the axis): a pair that cannot beat the closest
            // found is skipped, so the minimum, and which pair gives it, stay the same.
            if best.is_some_and(|b| circle_lower_bound(pivot, a, *m, *s) >= b.distance) {
                continue;
            }
            let (distance, t) = arc_point_distance(pivot, a, total, *m, *s);
            let closer = match best {
                Some(b) => distance < b.distance,
                None => true,
            };
            if closer {
                best = Some(SweepApproach {
                    distance,
                    moving: mi,
                    still: si,
                    angle_deg: t.to_degrees(),
                });
            }
        }
    }
    best
}

/// A lower bound on the distance from `s` to any point of the circle `m` describes about the
/// unit axis `a` through `pivot`: the differences of the heights along the axis and of the
/// radii from it, which every point of the circle keeps.
fn circle_lower_bound(pivot: [f64; 3], a: [f64; 3], m: [f64; 3], s: [f64; 3]) -> f64 {
    let (r, w) = (fsub(m, pivot), fsub(s, pivot));
    let (hr, hw) = (fdot(a, r), fdot(a, w));
    let radius = |v: [f64; 3], h: f64| (fdot(v, v) - h * h).max(0.0).sqrt();
    let (dh, dr) = (hr - hw, radius(r, hr) - radius(w, hw));
    // Shaved by a relative epsilon so rounding never makes the bound exceed the distance.
    (dh * dh + dr * dr).sqrt() * (1.0 - 1e-12)
}

/// Minimum distance between point `m` turned by t in [0, total] about unit `a` through `pivot`
/// and the fixed point `s`; returns (distance, t at the minimum).
pub fn arc_point_distance(
    pivot: [f64; 3],
    a: [f64; 3],
    total: f64,
    m: [f64; 3],
    s: [f64; 3],
) -> (f64, f64) {
    let r = fsub(m, pivot);
    let w = fsub(s, pivot);
    let r_par = fscale(a, fdot(a, r));
    let r_perp = fsub(r, r_par);
    let alpha = fdot(w, r_perp);
    let beta = fdot(w, fcross(a, r));
    let g = |t: f64| alpha * t.cos() + beta * t.sin();
    let peak = beta.atan2(alpha).rem_euclid(std::f64::consts::TAU);
    let mut best_t = if g(total) > g(0.0) { total } else { 0.0 };
    if peak <= total && g(peak) > g(best_t) {
        best_t = peak;
    }
    let squared = fdot(r, r) + fdot(w, w) - 2.0 * fdot(w, r_par) - 2.0 * g(best_t);
    (squared.max(0.0).sqrt(), best_t)
}

fn fsub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn fscale(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}

fn fdot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn fcross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Converts an integer vector to floating point (for the sweep check only).
pub fn to_f64(v: Vec3) -> [f64; 3] {
    v.map(f64::from)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extreme_coordinates_are_out_of_bounds_and_not_axes_without_overflow() {
        assert!(within_bounds([MAX_COORDINATE, -MAX_COORDINATE, 0]));
        assert!(!within_bounds([i32::MIN, 0, 0]));
        assert!(!within_bounds([0, i32::MAX, 0]));
        assert!(is_unit_axis([0, -1, 0]));
        assert!(!is_unit_axis([i32::MIN, 1, 0]));
        assert!(!is_unit_axis([i32::MAX, i32::MAX, i32::MAX]));
        assert!(!is_unit_axis([1, -1, 0]));
        assert!(!is_unit_axis([0, 0, 0]));
    }

    #[test]
    fn there_are_24_distinct_rotations_closed_under_composition() {
        let all = Rotation::all();
        assert_eq!(all.len(), 24);
        assert_eq!(all[0], Rotation::IDENTITY);
        let set: std::collections::BTreeSet<_> = all.iter().copied().collect();
        assert_eq!(set.len(), 24);
        for a in &all {
            assert_eq!(a.compose(&a.inverse()), Rotation::IDENTITY);
            for b in &all {
                assert!(set.contains(&a.compose(b)));
            }
        }
    }

    #[test]
    fn quarter_turn_about_z_is_counter_clockwise() {
        let r = Rotation::about_axis([0, 0, 1], 1);
        assert_eq!(r.map(|r| r.apply([1, 0, 0])), Some([0, 1, 0]));
        let r = Rotation::about_axis([0, 0, -1], 1);
        assert_eq!(r.map(|r| r.apply([1, 0, 0])), Some([0, -1, 0]));
        assert_eq!(Rotation::about_axis([1, 1, 0], 1), None);
    }

    #[test]
    fn closed_form_sweep_matches_dense_sampling() {
        let pivot = [0.5, -1.0, 0.0];
        let moving = [[2.0, 0.0, 1.0], [0.0, 1.0, -1.0]];
        let still = [[1.0, 2.0, 0.5], [-2.0, 0.0, 1.0]];
        for angle in [90.0, -90.0, 180.0, -270.0] {
            let found = sweep_closest_approach(pivot, [0.0, 0.0, 1.0], angle, &moving, &still);
            let mut sampled = f64::INFINITY;
            for step in 0..=20_000 {
                let t = (angle * f64::from(step) / 20_000.0).to_radians();
                for m in moving {
                    let r = fsub(m, pivot);
                    let turned = [
                        pivot[0] + r[0] * t.cos() - r[1] * t.sin(),
                        pivot[1] + r[0] * t.sin() + r[1] * t.cos(),
                        m[2],
                    ];
                    for s in still {
                        let d = fsub(turned, s);
                        sampled = sampled.min(fdot(d, d).sqrt());
                    }
                }
            }
            let found = found.map(|f| f.distance).unwrap_or(f64::NAN);
            assert!(
                (found - sampled).abs() < 1e-6,
                "{angle}: {found} vs {sampled}"
            );
        }
    }
}
