//! The motion of one joint turn, shared by every robot: where a moving point is part-way
//! through, how close its path comes to a still point, its length and bounding box.

use crate::geometry::{arc_point_distance, Vec3};

/// The motion of one joint turn: the moving side turns by `angle_deg` (right-handed, signed)
/// about `axis` through `pivot`. Points are the centres of whole modules or of a module's
/// parts (a block), in the robot's length unit.
#[derive(Clone, Debug, PartialEq)]
pub struct TurnMotion {
    pub pivot: [f64; 3],
    pub axis: Vec3,
    pub angle_deg: f64,
    /// Name and start position of each moving point (a module, or a part of one, whose
    /// module's name is repeated for its two blocks).
    pub moving: Vec<(String, [f64; 3])>,
    /// The smallest distance the model allows between a moving point and another one.
    pub limit: f64,
}

impl TurnMotion {
    /// Where a point of the moving side is after `fraction` (0 to 1) of the turn.
    pub fn position_at(&self, point: [f64; 3], fraction: f64) -> [f64; 3] {
        let (a, r, dot, cross) = self.frame(point);
        let t = (self.angle_deg * fraction).to_radians();
        // Rodrigues' rotation formula for a unit axis.
        let (sin, cos) = t.sin_cos();
        std::array::from_fn(|k| {
            self.pivot[k] + r[k] * cos + cross[k] * sin + a[k] * dot * (1.0 - cos)
        })
    }

    /// The smallest distance from the still point `point` to the path of the moving point
    /// `start` over the whole turn, in closed form (not sampled).
    pub fn distance_to_path(&self, start: [f64; 3], point: [f64; 3]) -> f64 {
        let a = self.axis.map(f64::from);
        // Turning by a negative angle about a is the same as a positive one about -a.
        let a = if self.angle_deg < 0.0 {
            a.map(|c| -c)
        } else {
            a
        };
        arc_point_distance(
            self.pivot,
            a,
            self.angle_deg.abs().to_radians(),
            start,
            point,
        )
        .0
    }

    /// The length of the path of the moving point `start` (its radius about the axis times
    /// the angle turned): no point of it moves farther than this during the turn.
    pub fn path_length(&self, start: [f64; 3]) -> f64 {
        let (_, r, dot, _) = self.frame(start);
        let radius = (r.iter().map(|c| c * c).sum::<f64>() - dot * dot)
            .max(0.0)
            .sqrt();
        radius * self.angle_deg.abs().to_radians()
    }

    /// The exact bounding box (low, high) of the path of the moving point `start`: its two
    /// ends, and the extremes of each coordinate that fall within the turn.
    pub fn path_box(&self, start: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let (_, r, _, cross) = self.frame(start);
        let total = self.angle_deg.to_radians();
        let mut low = start;
        let mut high = start;
        let mut include = |p: [f64; 3]| {
            for k in 0..3 {
                low[k] = low[k].min(p[k]);
                high[k] = high[k].max(p[k]);
            }
        };
        include(self.position_at(start, 1.0));
        for k in 0..3 {
            // Coordinate k varies as r_k cos t + cross_k sin t (plus a constant): extreme
            // where tan t = cross_k / r_k, and half a turn later.
            let peak = cross[k].atan2(r[k] - self.axis_component(k, start));
            for extreme in [peak, peak + std::f64::consts::PI] {
                if let Some(fraction) = fraction_of(extreme, total) {
                    include(self.position_at(start, fraction));
                }
            }
        }
        (low, high)
    }

    /// The axis (unit), the point relative to the pivot, its component along the axis and
    /// the axis crossed with it.
    fn frame(&self, point: [f64; 3]) -> ([f64; 3], [f64; 3], f64, [f64; 3]) {
        let a = self.axis.map(f64::from);
        let r = std::array::from_fn(|k| point[k] - self.pivot[k]);
        let dot = a[0] * r[0] + a[1] * r[1] + a[2] * r[2];
        let cross = [
            a[1] * r[2] - a[2] * r[1],
            a[2] * r[0] - a[0] * r[2],
            a[0] * r[1] - a[1] * r[0],
        ];
        (a, r, dot, cross)
    }

    /// Coordinate k of the part of `point` (relative to the pivot) along the axis.
    fn axis_component(&self, k: usize, point: [f64; 3]) -> f64 {
        let (a, _, dot, _) = self.frame(point);
        a[k] * dot
    }
}

/// The fraction of a turn by `total` radians (signed) at which the angle `t` (any turn of it)
/// is reached, if it is.
fn fraction_of(t: f64, total: f64) -> Option<f64> {
    if total == 0.0 {
        return None;
    }
    let tau = std::f64::consts::TAU;
    let t = if total > 0.0 {
        t.rem_euclid(tau)
    } else {
        -(-t).rem_euclid(tau)
    };
    let fraction = t / total;
    (0.0..=1.0).contains(&fraction).then_some(fraction)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Turns about each axis, both ways, of points off the axis and on it.
    fn motions() -> Vec<(TurnMotion, [f64; 3])> {
        let mut out = Vec::new();
        for axis in [[1, 0, 0], [0, -1, 0], [0, 0, 1]] {
            for angle_deg in [90.0, -180.0, 270.0] {
                let motion = TurnMotion {
                    pivot: [0.5, -1.0, 2.0],
                    axis,
                    angle_deg,
                    moving: Vec::new(),
                    limit: 1.2,
                };
                for start in [[2.5, 1.0, 3.0], [0.5, -1.0, 5.0], [-3.0, 0.0, 2.0]] {
                    out.push((motion.clone(), start));
                }
            }
        }
        out
    }

    fn dense(motion: &TurnMotion, start: [f64; 3]) -> Vec<[f64; 3]> {
        (0..=20_000)
            .map(|i| motion.position_at(start, f64::from(i) / 20_000.0))
            .collect()
    }

    #[test]
    fn path_boxes_are_the_exact_bounds_of_the_path() {
        for (motion, start) in motions() {
            let (low, high) = motion.path_box(start);
            let points = dense(&motion, start);
            for k in 0..3 {
                let min = points.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
                let max = points
                    .iter()
                    .map(|p| p[k])
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!((low[k] - min).abs() < 1e-6, "{motion:?} {start:?} {k}");
                assert!((high[k] - max).abs() < 1e-6, "{motion:?} {start:?} {k}");
            }
        }
    }

    #[test]
    fn distance_to_a_path_and_its_length_match_dense_sampling() {
        let point = [1.0, 0.5, 2.5];
        for (motion, start) in motions() {
            let points = dense(&motion, start);
            let distance = |p: &[f64; 3]| {
                ((p[0] - point[0]).powi(2) + (p[1] - point[1]).powi(2) + (p[2] - point[2]).powi(2))
                    .sqrt()
            };
            let sampled = points.iter().map(distance).fold(f64::INFINITY, f64::min);
            assert!((motion.distance_to_path(start, point) - sampled).abs() < 1e-6);
            let walked: f64 = points
                .windows(2)
                .map(|w| {
                    ((w[0][0] - w[1][0]).powi(2)
                        + (w[0][1] - w[1][1]).powi(2)
                        + (w[0][2] - w[1][2]).powi(2))
                    .sqrt()
                })
                .sum();
            assert!((motion.path_length(start) - walked).abs() < 1e-6);
        }
    }
}
