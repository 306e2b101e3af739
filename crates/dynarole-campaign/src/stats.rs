//! Figures per point (axis, value, protocol): success rate with its Wilson 95 % interval,
//! median completion time of the successful runs, mean packets sent over all runs.

use crate::results::{Outcome, Row};
use serde::Serialize;
use std::collections::BTreeMap;

/// z for a two-sided 95 % interval.
const Z95: f64 = 1.959_963_984_540_054;

/// One line of `summary.csv`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointSummary {
    pub axis: String,
    pub value: f64,
    pub protocol: String,
    pub runs: u64,
    pub successes: u64,
    pub success_rate: f64,
    pub success_low: f64,
    pub success_high: f64,
    pub timeouts: u64,
    pub wrong_configurations: u64,
    pub violations: u64,
    /// Runs that ended stopped by a module's failure policy (`Outcome::Stopped`).
    pub stopped: u64,
    pub median_completion_ms: Option<f64>,
    pub mean_packets_sent: f64,
}

/// The Wilson score interval at 95 % for `successes` out of `n` (0 to 1 when n is 0).
pub fn wilson(successes: u64, n: u64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let n = n as f64;
    let p = successes as f64 / n;
    let z2 = Z95 * Z95;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = Z95 / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    ((centre - half).max(0.0), (centre + half).min(1.0))
}

/// The median of `values` (the mean of the two middle ones for an even count).
pub fn median(values: &mut [f64]) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => values.get(n / 2).copied(),
        _ => Some((values.get(n / 2 - 1)? + values.get(n / 2)?) / 2.0),
    }
}

/// One summary per (axis, value, protocol), in axis order, then value, then protocol.
pub fn summarise(rows: &[Row]) -> Vec<PointSummary> {
    let mut groups: BTreeMap<(u8, u64, &str), Vec<&Row>> = BTreeMap::new();
    for row in rows {
        let axis = crate::plan::Axis::from_name(&row.axis).map_or(u8::MAX, |a| a as u8);
        groups
            .entry((axis, row.value.to_bits(), &row.protocol))
            .or_default()
            .push(row);
    }
    groups.into_values().map(|g| point(&g)).collect()
}

fn point(rows: &[&Row]) -> PointSummary {
    let count = |o: Outcome| rows.iter().filter(|r| r.outcome == o).count() as u64;
    let runs = rows.len() as u64;
    let successes = count(Outcome::Success);
    let (success_low, success_high) = wilson(successes, runs);
    let mut times: Vec<f64> = rows
        .iter()
        .filter(|r| r.outcome == Outcome::Success)
        .filter_map(|r| r.completion_ms)
        .collect();
    let packets: u64 = rows.iter().map(|r| r.packets_sent).sum();
    let first = rows.first();
    PointSummary {
        axis: first.map(|r| r.axis.clone()).unwrap_or_default(),
        value: first.map_or(0.0, |r| r.value),
        protocol: first.map(|r| r.protocol.clone()).unwrap_or_default(),
        runs,
        successes,
        success_rate: if runs == 0 {
            0.0
        } else {
            successes as f64 / runs as f64
        },
        success_low,
        success_high,
        timeouts: count(Outcome::Timeout),
        wrong_configurations: count(Outcome::WrongConfiguration),
        violations: count(Outcome::Violation),
        stopped: count(Outcome::Stopped),
        median_completion_ms: median(&mut times),
        mean_packets_sent: if runs == 0 {
            0.0
        } else {
            packets as f64 / runs as f64
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_known_values() {
        let (lo, hi) = wilson(8, 10);
        assert!((lo - 0.4902).abs() < 1e-3 && (hi - 0.9433).abs() < 1e-3);
        let (lo, hi) = wilson(10, 10);
        assert!((lo - 0.7225).abs() < 1e-3 && (hi - 1.0).abs() < 1e-9);
        assert_eq!(wilson(0, 0), (0.0, 1.0));
    }

    #[test]
    fn median_of_even_and_odd() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&mut []), None);
    }
}
