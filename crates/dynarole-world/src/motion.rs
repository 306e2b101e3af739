//! Motions, the one vocabulary of what a robot's operation does in space, for every robot:
//! legs (a rotation about an axis through a point, a translation) done one after another,
//! the rigid parts they carry, and the points their sweep is checked with. Where a moving
//! point is part-way through, how close its path comes to a still point, its length and
//! bounding box are all exact (closed form), never sampled.

use crate::geometry::{arc_point_distance, sweep_closest_approach, Vec3};
use serde::{Deserialize, Serialize};

/// One leg of a motion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Leg {
    /// A turn by `angle_deg` (right-handed, signed) about the unit `axis` through `pivot`: a
    /// joint turn, or a cube's pivot about an edge.
    Rotate {
        pivot: [f64; 3],
        axis: [f64; 3],
        angle_deg: f64,
    },
    /// A straight move by `by`: a slide.
    Translate { by: [f64; 3] },
}

/// A rigid part a motion carries: a whole module (`part: None`), or one part of a module
/// (by its index in the robot's drawing, `Drawing::parts`) while the rest stays.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Carried {
    pub module: String,
    pub part: Option<usize>,
}

/// What one operation does in space. Its legs are done one after another, each over an equal
/// share of the operation's duration; a motion without legs (a connector latching inside its
/// module) moves nothing a sweep or a drawing sees. Points are in the robot's length unit.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    pub legs: Vec<Leg>,
    /// What it moves, for the drawing and the links that break while it lasts.
    pub carried: Vec<Carried>,
    /// The points its sweep is checked with (the robot's collision geometry): name of the
    /// module each belongs to and its start position (a module may have several).
    pub moving: Vec<(String, [f64; 3])>,
    /// The smallest distance the model allows between a moving point and another one.
    pub limit: f64,
}

impl Motion {
    /// A joint turn of `angle_deg` about the lattice `axis` through `pivot`.
    pub fn turn(pivot: [f64; 3], axis: Vec3, angle_deg: f64, limit: f64) -> Motion {
        Motion {
            legs: vec![Leg::Rotate {
                pivot,
                axis: axis.map(f64::from),
                angle_deg,
            }],
            carried: Vec::new(),
            moving: Vec::new(),
            limit,
        }
    }

    /// An operation that moves no rigid part (a connector's latch, inside its module).
    pub fn in_place() -> Motion {
        Motion {
            legs: Vec::new(),
            carried: Vec::new(),
            moving: Vec::new(),
            limit: 0.0,
        }
    }

    /// Whether it has legs (a motion without is decided by running orders, not by sweeps).
    pub fn moves(&self) -> bool {
        !self.legs.is_empty()
    }

    /// Whether every leg is a rotation: a turn, as messages call it.
    pub fn is_turn(&self) -> bool {
        self.moves() && self.legs.iter().all(|l| matches!(l, Leg::Rotate { .. }))
    }

    /// Where a moving point that starts at `point` is after `fraction` (0 to 1) of the motion.
    pub fn position_at(&self, point: [f64; 3], fraction: f64) -> [f64; 3] {
        self.along(fraction, point, |leg, p, f| leg.position_at(p, f))
    }

    /// Where a direction carried by the motion (a part's up axis) points after `fraction`:
    /// rotations turn it, translations leave it.
    pub fn direction_at(&self, direction: [f64; 3], fraction: f64) -> [f64; 3] {
        self.along(fraction, direction, |leg, d, f| leg.direction_at(d, f))
    }

    /// The smallest distance from the still point `point` to the whole path of the moving
    /// point `start`.
    pub fn distance_to_path(&self, start: [f64; 3], point: [f64; 3]) -> f64 {
        self.leg_starts(start)
            .map(|(leg, from)| leg.distance_to_path(from, point))
            .fold(f64::INFINITY, f64::min)
    }

    /// The length of the path of the moving point `start`: no point of it moves farther than
    /// this during the motion.
    pub fn path_length(&self, start: [f64; 3]) -> f64 {
        self.leg_starts(start)
            .map(|(leg, from)| leg.path_length(from))
            .sum()
    }

    /// The exact bounding box (low, high) of the path of the moving point `start`.
    pub fn path_box(&self, start: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let mut bounds = (start, start);
        for (leg, from) in self.leg_starts(start) {
            let (low, high) = leg.path_box(from);
            for k in 0..3 {
                bounds.0[k] = bounds.0[k].min(low[k]);
                bounds.1[k] = bounds.1[k].max(high[k]);
            }
        }
        bounds
    }

    /// The closest approach of the moving points `moving` (start positions), over the whole
    /// motion, to the `still` points; `None` when either list is empty.
    pub fn sweep_approach(&self, moving: &[[f64; 3]], still: &[[f64; 3]]) -> Option<f64> {
        if let [leg] = self.legs.as_slice() {
            // One leg (a joint turn): its points start where they are, no copy.
            return leg.sweep_approach(moving, still);
        }
        let mut starts = moving.to_vec();
        let mut best: Option<f64> = None;
        for leg in &self.legs {
            let found = leg.sweep_approach(&starts, still);
            if let Some(d) = found {
                best = Some(best.map_or(d, |b| b.min(d)));
            }
            starts
                .iter_mut()
                .for_each(|p| *p = leg.position_at(*p, 1.0));
        }
        best
    }

    /// `apply(leg, value, fraction of that leg)` over every leg reached by `fraction` of the
    /// whole motion: the legs before it done fully, then that one in part.
    fn along(
        &self,
        fraction: f64,
        start: [f64; 3],
        apply: impl Fn(&Leg, [f64; 3], f64) -> [f64; 3],
    ) -> [f64; 3] {
        let n = self.legs.len();
        if n == 1 {
            // One leg: its own fraction, exactly (the common case, a joint turn).
            return apply(&self.legs[0], start, fraction);
        }
        let scaled = fraction.clamp(0.0, 1.0) * n as f64;
        let mut value = start;
        for (k, leg) in self.legs.iter().enumerate() {
            let share = (scaled - k as f64).clamp(0.0, 1.0);
            if share <= 0.0 {
                break;
            }
            value = apply(leg, value, share);
        }
        value
    }

    /// Each leg with where the moving point `start` is when it begins.
    fn leg_starts(&self, start: [f64; 3]) -> impl Iterator<Item = (&Leg, [f64; 3])> {
        self.legs.iter().scan(start, |at, leg| {
            let from = *at;
            *at = leg.position_at(from, 1.0);
            Some((leg, from))
        })
    }
}

impl Leg {
    /// Where a point is after `fraction` (0 to 1) of this leg.
    pub fn position_at(&self, point: [f64; 3], fraction: f64) -> [f64; 3] {
        match self {
            Leg::Rotate {
                pivot, angle_deg, ..
            } => {
                let (a, r, dot, cross) = self.frame(point);
                let t = (angle_deg * fraction).to_radians();
                // Rodrigues' rotation formula for a unit axis.
                let (sin, cos) = t.sin_cos();
                std::array::from_fn(|k| {
                    pivot[k] + r[k] * cos + cross[k] * sin + a[k] * dot * (1.0 - cos)
                })
            }
            Leg::Translate { by } => std::array::from_fn(|k| point[k] + by[k] * fraction),
        }
    }

    /// A direction after `fraction` of this leg.
    fn direction_at(&self, direction: [f64; 3], fraction: f64) -> [f64; 3] {
        match self {
            Leg::Rotate { pivot, .. } => {
                let tip =
                    self.position_at(std::array::from_fn(|i| pivot[i] + direction[i]), fraction);
                std::array::from_fn(|i| tip[i] - pivot[i])
            }
            Leg::Translate { .. } => direction,
        }
    }

    /// The smallest distance from the still point `point` to the path of `start` over this
    /// leg, in closed form.
    fn distance_to_path(&self, start: [f64; 3], point: [f64; 3]) -> f64 {
        match self {
            Leg::Rotate {
                pivot,
                axis,
                angle_deg,
            } => {
                // Turning by a negative angle about a is the same as a positive one about -a.
                let a = if *angle_deg < 0.0 {
                    axis.map(|c| -c)
                } else {
                    *axis
                };
                arc_point_distance(*pivot, a, angle_deg.abs().to_radians(), start, point).0
            }
            Leg::Translate { by } => segment_point_distance(start, *by, point),
        }
    }

    /// The length of the path of `start` over this leg.
    fn path_length(&self, start: [f64; 3]) -> f64 {
        match self {
            Leg::Rotate { angle_deg, .. } => {
                let (_, r, dot, _) = self.frame(start);
                let radius = (r.iter().map(|c| c * c).sum::<f64>() - dot * dot)
                    .max(0.0)
                    .sqrt();
                radius * angle_deg.abs().to_radians()
            }
            Leg::Translate { by } => norm(*by),
        }
    }

    /// The exact bounding box of the path of `start` over this leg: its two ends, and for a
    /// rotation the extremes of each coordinate that fall within the turn.
    fn path_box(&self, start: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let mut low = start;
        let mut high = start;
        let mut include = |p: [f64; 3]| {
            for k in 0..3 {
                low[k] = low[k].min(p[k]);
                high[k] = high[k].max(p[k]);
            }
        };
        include(self.position_at(start, 1.0));
        if let Leg::Rotate { angle_deg, .. } = self {
            let (a, r, dot, cross) = self.frame(start);
            let total = angle_deg.to_radians();
            for k in 0..3 {
                // Coordinate k varies as r_k cos t + cross_k sin t (plus a constant): extreme
                // where tan t = cross_k / r_k, and half a turn later.
                let peak = cross[k].atan2(r[k] - a[k] * dot);
                for extreme in [peak, peak + std::f64::consts::PI] {
                    if let Some(fraction) = fraction_of(extreme, total) {
                        include(self.position_at(start, fraction));
                    }
                }
            }
        }
        (low, high)
    }

    /// The closest approach of `moving` over this leg to `still`.
    fn sweep_approach(&self, moving: &[[f64; 3]], still: &[[f64; 3]]) -> Option<f64> {
        match self {
            Leg::Rotate {
                pivot,
                axis,
                angle_deg,
            } => {
                sweep_closest_approach(*pivot, *axis, *angle_deg, moving, still).map(|a| a.distance)
            }
            Leg::Translate { by } => moving
                .iter()
                .flat_map(|m| still.iter().map(|s| segment_point_distance(*m, *by, *s)))
                .reduce(f64::min),
        }
    }

    /// For a rotation: the axis, the point relative to the pivot, its component along the
    /// axis and the axis crossed with it (zeros for a translation).
    fn frame(&self, point: [f64; 3]) -> ([f64; 3], [f64; 3], f64, [f64; 3]) {
        let Leg::Rotate { pivot, axis, .. } = self else {
            return ([0.0; 3], [0.0; 3], 0.0, [0.0; 3]);
        };
        let a = *axis;
        let r: [f64; 3] = std::array::from_fn(|k| point[k] - pivot[k]);
        let dot = a[0] * r[0] + a[1] * r[1] + a[2] * r[2];
        let cross = [
            a[1] * r[2] - a[2] * r[1],
            a[2] * r[0] - a[0] * r[2],
            a[0] * r[1] - a[1] * r[0],
        ];
        (a, r, dot, cross)
    }
}

/// The distance from `point` to the segment from `start` to `start + by`.
fn segment_point_distance(start: [f64; 3], by: [f64; 3], point: [f64; 3]) -> f64 {
    let w: [f64; 3] = std::array::from_fn(|k| point[k] - start[k]);
    let length_squared = by.iter().map(|c| c * c).sum::<f64>();
    let t = if length_squared > 0.0 {
        ((w[0] * by[0] + w[1] * by[1] + w[2] * by[2]) / length_squared).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(std::array::from_fn(|k| w[k] - by[k] * t))
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
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

    /// Turns about each axis, both ways, of points off the axis and on it; slides; and
    /// two-leg motions (a corner slide, a pivot then a slide).
    fn motions() -> Vec<(Motion, [f64; 3])> {
        let mut legs = Vec::new();
        for axis in [[1, 0, 0], [0, -1, 0], [0, 0, 1]] {
            for angle_deg in [90.0, -180.0, 270.0] {
                legs.push(vec![Leg::Rotate {
                    pivot: [0.5, -1.0, 2.0],
                    axis: axis.map(f64::from),
                    angle_deg,
                }]);
            }
        }
        let slide = |by| Leg::Translate { by };
        legs.push(vec![slide([1.0, 0.0, 0.0])]);
        legs.push(vec![slide([0.0, 2.0, 0.0]), slide([0.0, 0.0, -1.0])]);
        let pivot = Leg::Rotate {
            pivot: [0.5, 0.5, 0.0],
            axis: [0.0, 0.0, 1.0],
            angle_deg: 90.0,
        };
        legs.push(vec![pivot, slide([-1.0, 0.0, 0.5])]);
        let mut out = Vec::new();
        for legs in legs {
            let motion = Motion {
                legs,
                carried: Vec::new(),
                moving: Vec::new(),
                limit: 1.2,
            };
            for start in [[2.5, 1.0, 3.0], [0.5, -1.0, 5.0], [-3.0, 0.0, 2.0]] {
                out.push((motion.clone(), start));
            }
        }
        out
    }

    #[test]
    fn a_motion_of_one_leg_is_that_leg_fraction_for_fraction() {
        let leg = Leg::Rotate {
            pivot: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            angle_deg: 90.0,
        };
        let motion = Motion {
            legs: vec![leg.clone()],
            ..Motion::in_place()
        };
        for f in [0.0, 0.25, 0.5, 1.0] {
            assert_eq!(
                motion.position_at([1.0, 0.0, 0.0], f),
                leg.position_at([1.0, 0.0, 0.0], f)
            );
        }
    }

    #[test]
    fn legs_take_equal_shares_one_after_another() {
        let slide = |by| Leg::Translate { by };
        let motion = Motion {
            legs: vec![slide([1.0, 0.0, 0.0]), slide([0.0, 1.0, 0.0])],
            ..Motion::in_place()
        };
        assert_eq!(motion.position_at([0.0; 3], 0.25), [0.5, 0.0, 0.0]);
        assert_eq!(motion.position_at([0.0; 3], 0.5), [1.0, 0.0, 0.0]);
        assert_eq!(motion.position_at([0.0; 3], 0.75), [1.0, 0.5, 0.0]);
        assert_eq!(motion.position_at([0.0; 3], 1.0), [1.0, 1.0, 0.0]);
        // The corner is the closest point of the path to (2, -1, 0).
        let corner = motion.distance_to_path([0.0; 3], [2.0, -1.0, 0.0]);
        assert!((corner - 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(motion.path_length([0.0; 3]), 2.0);
        assert!(!Motion::in_place().moves() && motion.moves() && !motion.is_turn());
    }

    #[test]
    fn a_sweep_over_legs_finds_the_approach_of_the_later_leg() {
        let motion = Motion {
            legs: vec![
                Leg::Translate {
                    by: [2.0, 0.0, 0.0],
                },
                Leg::Translate {
                    by: [0.0, 2.0, 0.0],
                },
            ],
            ..Motion::in_place()
        };
        let approach = motion.sweep_approach(&[[0.0; 3]], &[[3.0, 1.0, 0.0]]);
        assert_eq!(approach, Some(1.0));
        assert_eq!(motion.sweep_approach(&[], &[[3.0, 1.0, 0.0]]), None);
    }

    fn dense(motion: &Motion, start: [f64; 3]) -> Vec<[f64; 3]> {
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
