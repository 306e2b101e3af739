//! `summary.md`: the summary as Markdown tables, one per swept axis (a row per value, a
//! column per protocol: successes out of runs with the 95 % interval, the median completion
//! time, and the runs with ordering violations), ready to paste into a report.

use crate::plan::Axis;
use crate::stats::PointSummary;
use dynarole_codegen::Variant;
use std::fmt::Write;

/// Columns in this order (the shared-state protocols, then the token from weakest to most
/// persistent); others after them.
const ORDER: [Variant; 6] = [
    Variant::Lattice,
    Variant::Paper,
    Variant::TokenPlain,
    Variant::Token32,
    Variant::Token128,
    Variant::TokenUnlimited,
];

/// The tables, axis by axis in campaign order.
pub fn markdown(summaries: &[PointSummary]) -> String {
    let mut out = String::new();
    for axis in Axis::ALL {
        let on_axis: Vec<&PointSummary> =
            summaries.iter().filter(|s| s.axis == axis.name()).collect();
        if !on_axis.is_empty() {
            table(&mut out, axis, &on_axis);
        }
    }
    out
}

fn table(out: &mut String, axis: Axis, on_axis: &[&PointSummary]) {
    let mut protocols: Vec<&str> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    for s in on_axis {
        if !protocols.contains(&s.protocol.as_str()) {
            protocols.push(&s.protocol);
        }
        if !values.contains(&s.value) {
            values.push(s.value);
        }
    }
    protocols.sort_by_key(|p| {
        ORDER
            .iter()
            .position(|o| o.name() == *p)
            .unwrap_or(ORDER.len())
    });
    let _ = writeln!(out, "### {}\n", axis.label());
    let _ = write!(out, "| {} |", axis.name());
    for p in &protocols {
        let _ = write!(out, " {p} |");
    }
    out.push_str("\n|---|");
    out.push_str(&"---|".repeat(protocols.len()));
    out.push('\n');
    for value in values {
        let _ = write!(out, "| {value} |");
        for p in &protocols {
            let cell = on_axis
                .iter()
                .find(|s| s.value == value && s.protocol == *p)
                .map_or_else(|| "-".to_string(), |s| cell(s));
            let _ = write!(out, " {cell} |");
        }
        out.push('\n');
    }
    out.push('\n');
}

/// `successes/runs (low-high %), median s[, k with violations]`.
fn cell(s: &PointSummary) -> String {
    let mut text = format!(
        "{}/{} ({:.1}-{:.1} %)",
        s.successes,
        s.runs,
        s.success_low * 100.0,
        s.success_high * 100.0
    );
    match s.median_completion_ms {
        Some(ms) => {
            let _ = write!(text, ", {:.2} s", ms / 1000.0);
        }
        None => text.push_str(", -"),
    }
    if s.violations > 0 {
        let _ = write!(text, ", {} with violations", s.violations);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(value: f64, protocol: &str, successes: u64, violations: u64) -> PointSummary {
        PointSummary {
            axis: "loss".into(),
            value,
            protocol: protocol.into(),
            runs: 10,
            successes,
            success_rate: successes as f64 / 10.0,
            success_low: 0.5,
            success_high: 1.0,
            timeouts: 0,
            wrong_configurations: 0,
            stopped: 0,
            violations,
            median_completion_ms: (successes > 0).then_some(31_150.0),
            mean_packets_sent: 1.0,
        }
    }

    #[test]
    fn one_row_per_value_and_one_column_per_protocol() {
        let text = markdown(&[
            point(0.0, "lattice", 10, 0),
            point(0.0, "token-32", 0, 3),
            point(0.2, "lattice", 9, 0),
        ]);
        assert_eq!(
            text,
            "### packet loss probability\n\n| loss | lattice | token-32 |\n|---|---|---|\n\
             | 0 | 10/10 (50.0-100.0 %), 31.15 s | 0/10 (50.0-100.0 %), -, 3 with violations |\n\
             | 0.2 | 9/10 (50.0-100.0 %), 31.15 s | - |\n\n"
        );
    }
}
