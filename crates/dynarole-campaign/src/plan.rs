//! The runs of a campaign, in a fixed order: axis by axis (loss, dead links, resets), value by
//! value, protocol by protocol, seed by seed. A run's index is its place in this order, and a
//! run depends only on its parameters and its seed.

use crate::spec::{CampaignFile, SpecError};
use dynarole_codegen::Variant;
use dynarole_sim::{RandomResets, Scenario};

/// A swept fault axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Axis {
    Loss,
    DeadLinkP,
    ResetProbability,
    /// Loss, dead links and resets together, scaled by one level.
    Combined,
}

impl Axis {
    pub const ALL: [Axis; 4] = [
        Axis::Loss,
        Axis::DeadLinkP,
        Axis::ResetProbability,
        Axis::Combined,
    ];

    /// The name in the campaign file and in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Axis::Loss => "loss",
            Axis::DeadLinkP => "dead_link_p",
            Axis::ResetProbability => "reset_probability",
            Axis::Combined => "combined",
        }
    }

    /// A label for plots.
    pub fn label(self) -> &'static str {
        match self {
            Axis::Loss => "packet loss probability",
            Axis::DeadLinkP => "dead-link probability",
            Axis::ResetProbability => "reset probability per check",
            Axis::Combined => "combined fault level (loss, dead links, resets scaled together)",
        }
    }

    pub fn from_name(name: &str) -> Option<Axis> {
        Axis::ALL.into_iter().find(|a| a.name() == name)
    }
}

/// The fault parameters of one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Faults {
    pub loss: f64,
    pub dead_link_p: f64,
    pub dead_loss: f64,
    /// (interval in ms, probability) of random resets.
    pub resets: Option<(u64, f64)>,
}

/// One run to do.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedRun {
    pub index: u64,
    pub axis: Axis,
    pub value: f64,
    pub protocol: Variant,
    pub seed: u64,
    pub faults: Faults,
}

impl PlannedRun {
    /// The base scenario with this run's faults.
    pub fn scenario(&self, base: &Scenario) -> Scenario {
        let mut s = base.clone();
        s.network.loss = self.faults.loss;
        s.network.dead_link_p = self.faults.dead_link_p;
        s.network.dead_loss = self.faults.dead_loss;
        s.random_resets = self
            .faults
            .resets
            .map(|(interval_ms, probability)| RandomResets {
                interval_ms,
                probability,
            });
        s
    }
}

pub use crate::limits::MAX_RUNS;

/// Every run of the campaign, in index order, computed from its index when asked for: a plan
/// is the points of the sweep and nothing per run, so its size does not grow with `seeds`.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    points: Vec<(Axis, f64, Faults)>,
    protocols: Vec<Variant>,
    seeds: u64,
    first_seed: u64,
}

/// The plan of `campaign`; fails, naming the field, when it would have more than
/// [`MAX_RUNS`] runs.
pub fn plan(campaign: &CampaignFile) -> Result<Plan, SpecError> {
    let mut points = Vec::new();
    for axis in Axis::ALL {
        for (value, faults) in self::points(campaign, axis)? {
            points.push((axis, value, faults));
        }
    }
    let plan = Plan {
        points,
        protocols: campaign.protocols.clone(),
        seeds: campaign.seeds,
        first_seed: campaign.first_seed,
    };
    let runs = plan
        .runs_per_point()
        .and_then(|r| r.checked_mul(plan.points.len() as u64));
    match runs {
        Some(n) if n <= MAX_RUNS => Ok(plan),
        _ => Err(SpecError::new(
            "seeds",
            format!(
                "{} points x {} protocols x {} seeds is more than {MAX_RUNS} runs",
                plan.points.len(),
                plan.protocols.len(),
                plan.seeds
            ),
        )),
    }
}

impl Plan {
    fn runs_per_point(&self) -> Option<u64> {
        (self.protocols.len() as u64).checked_mul(self.seeds)
    }

    /// The number of runs (at most [`MAX_RUNS`]).
    pub fn len(&self) -> u64 {
        self.runs_per_point().unwrap_or(0) * self.points.len() as u64
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The run with this index, if the plan has it.
    pub fn get(&self, index: u64) -> Option<PlannedRun> {
        let per_point = self.runs_per_point().filter(|&n| n > 0)?;
        let point = usize::try_from(index / per_point).ok()?;
        let &(axis, value, faults) = self.points.get(point)?;
        let within = index % per_point;
        let protocol = *self
            .protocols
            .get(usize::try_from(within / self.seeds).ok()?)?;
        Some(PlannedRun {
            index,
            axis,
            value,
            protocol,
            seed: self.first_seed.wrapping_add(within % self.seeds),
            faults,
        })
    }

    /// Every run, in index order.
    pub fn iter(&self) -> impl Iterator<Item = PlannedRun> + '_ {
        (0..self.len()).filter_map(|i| self.get(i))
    }
}

/// The values of `axis` and the faults at each (none when the axis is not swept).
fn points(campaign: &CampaignFile, axis: Axis) -> Result<Vec<(f64, Faults)>, SpecError> {
    let sweep = &campaign.sweep;
    let network = &campaign.scenario.network;
    let base = Faults {
        loss: network.loss,
        dead_link_p: network.dead_link_p,
        dead_loss: network.dead_loss,
        resets: campaign
            .scenario
            .random_resets
            .as_ref()
            .map(|r| (r.interval_ms, r.probability)),
    };
    let range = match axis {
        Axis::Loss => &sweep.loss,
        Axis::DeadLinkP => &sweep.dead_link_p,
        Axis::ResetProbability => &sweep.reset_probability,
        Axis::Combined => &sweep.combined,
    };
    let Some(range) = range else {
        return Ok(Vec::new());
    };
    let values = range.values(&format!("sweep.{}", axis.name()))?;
    Ok(values
        .into_iter()
        .map(|v| (v, faults_at(campaign, axis, v, base)))
        .collect())
}

fn faults_at(campaign: &CampaignFile, axis: Axis, value: f64, base: Faults) -> Faults {
    let sweep = &campaign.sweep;
    match axis {
        Axis::Loss => Faults {
            loss: value,
            ..base
        },
        Axis::DeadLinkP => Faults {
            loss: sweep.dead_background_loss.unwrap_or(base.loss),
            dead_link_p: value,
            dead_loss: sweep.dead_loss.unwrap_or(base.dead_loss),
            ..base
        },
        Axis::ResetProbability => Faults {
            resets: Some((sweep.reset_interval_ms.unwrap_or(1000), value)),
            ..base
        },
        Axis::Combined => {
            let interval = sweep
                .combined_reset_interval_ms
                .or(sweep.reset_interval_ms)
                .unwrap_or(1000);
            let scaled = |at_one: Option<f64>| round9(at_one.unwrap_or(0.0) * value);
            let reset_p = scaled(sweep.combined_reset_probability);
            Faults {
                loss: scaled(sweep.combined_loss),
                dead_link_p: scaled(sweep.combined_dead_link_p),
                dead_loss: sweep.dead_loss.unwrap_or(base.dead_loss),
                resets: (reset_p > 0.0).then_some((interval, reset_p)),
            }
        }
    }
}

/// Rounded to 9 decimals, as the ranges' values are, so 0.1 x 0.3 is written 0.03.
fn round9(v: f64) -> f64 {
    (v * 1e9).round() / 1e9
}
