//! The campaign file (TOML): what to run, the base scenario, the fault axes to sweep. Every
//! field is documented in the crate's `README.md`; unknown fields are errors, and every error
//! names its field.

use dynarole_codegen::choice;
use dynarole_codegen::{OnFailure, PaperMerge, Variant, MAX_RETRIES};
use dynarole_sim::{PresetName, Scenario};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The most points one axis may have (a typo in `step` should not plan a billion runs).
const MAX_POINTS_PER_AXIS: usize = 10_000;

/// `{ from, to, step }`, both ends included.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    pub from: f64,
    pub to: f64,
    pub step: f64,
}

/// The fault axes. Each axis is swept on its own (one family of points), the others staying
/// at the base scenario's values, as in the original batches.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    pub loss: Option<Range>,
    pub dead_link_p: Option<Range>,
    /// Loss on every channel during the dead-link sweep (default: the base scenario's).
    pub dead_background_loss: Option<f64>,
    /// Loss on a dead channel during the dead-link sweep (default: the base scenario's).
    pub dead_loss: Option<f64>,
    pub reset_probability: Option<Range>,
    /// Required with `reset_probability`.
    pub reset_interval_ms: Option<u64>,
    /// The three faults at once: a level from 0 to 1 that scales `combined_loss`,
    /// `combined_dead_link_p` and `combined_reset_probability` (all required with it).
    pub combined: Option<Range>,
    pub combined_loss: Option<f64>,
    pub combined_dead_link_p: Option<f64>,
    pub combined_reset_probability: Option<f64>,
    /// Reset check interval of the combined axis (default: `reset_interval_ms`, else 1 s).
    pub combined_reset_interval_ms: Option<u64>,
}

/// The campaign file as written.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignFile {
    pub file: PathBuf,
    #[serde(default)]
    pub plugins: Vec<PathBuf>,
    pub sequences: Vec<String>,
    pub from: PathBuf,
    pub expect: Option<PathBuf>,
    /// The protocols to compare, as the protocol table names its variants
    /// (`dynarole_codegen::Variant`): `lattice`, `lattice-fixed`, `paper`, `token-plain`,
    /// `token-32`, `token-128`, `token-unlimited`.
    #[serde(deserialize_with = "choice::deserialize_list")]
    pub protocols: Vec<Variant>,
    pub preset: Option<PresetName>,
    pub timeout_ms: Option<u64>,
    pub seeds: u64,
    #[serde(default)]
    pub first_seed: u64,
    #[serde(default)]
    pub options: ProtocolOptions,
    #[serde(default)]
    pub scenario: Scenario,
    #[serde(default)]
    pub sweep: Sweep,
    /// Each path field (`file`, `plugins[i]`, `from`, `expect`) as written, before
    /// `resolve_paths`: errors reading a file name the field and both paths.
    #[serde(skip)]
    pub written: Vec<(String, PathBuf)>,
}

/// An error in the campaign file: the field, the message, where in the text.
pub type SpecError = dynarole_core::toml_error::TomlError;

fn error(field: &str, message: impl Into<String>) -> SpecError {
    SpecError::new(field, message)
}

impl CampaignFile {
    /// Parses and checks a campaign; relative paths are made relative to `dir` (the
    /// campaign file's directory).
    /// Errors carry the span of their field in `text`.
    pub fn parse(text: &str, dir: &Path) -> Result<CampaignFile, SpecError> {
        let raw: toml::Table = toml::from_str(text).map_err(|e| SpecError::from_de(&e))?;
        reject_overridden(&raw).map_err(|e| e.locate(text))?;
        let mut campaign: CampaignFile =
            toml::from_str(text).map_err(|e| SpecError::from_de(&e))?;
        if let Some(preset) = campaign.preset.clone() {
            campaign.scenario.network.preset = preset;
        }
        if let Some(timeout) = campaign.timeout_ms {
            campaign.scenario.timeout_ms = timeout;
        }
        campaign.check().map_err(|e| e.locate(text))?;
        campaign.resolve_paths(dir);
        Ok(campaign)
    }

    fn check(&self) -> Result<(), SpecError> {
        if self.sequences.is_empty() {
            return Err(error("sequences", "name at least one sequence"));
        }
        self.options.check()?;
        if self.protocols.is_empty() {
            return Err(error("protocols", "name at least one protocol"));
        }
        let mut sorted = self.protocols.clone();
        sorted.sort();
        sorted.dedup();
        if sorted.len() != self.protocols.len() {
            return Err(error("protocols", "a protocol is listed twice"));
        }
        if self.seeds == 0 || self.seeds > crate::limits::MAX_RUNS {
            let most = crate::limits::MAX_RUNS;
            return Err(error(
                "seeds",
                format!("expected 1 to {most}, found {}", self.seeds),
            ));
        }
        self.scenario.check().map_err(|e| e.nested_in("scenario"))?;
        self.sweep.check()
    }

    fn resolve_paths(&mut self, dir: &Path) {
        let mut written = Vec::new();
        let mut join = |field: String, p: &mut PathBuf| {
            written.push((field, p.clone()));
            if p.is_relative() {
                *p = dir.join(&*p);
            }
        };
        join("file".into(), &mut self.file);
        for (i, plugin) in self.plugins.iter_mut().enumerate() {
            join(format!("plugins[{i}]"), plugin);
        }
        join("from".into(), &mut self.from);
        if let Some(e) = &mut self.expect {
            join("expect".into(), e);
        }
        self.written = written;
    }

    /// How `field` (a path field) was written in the file, if it was.
    pub fn written(&self, field: &str) -> Option<&Path> {
        self.written
            .iter()
            .find(|(f, _)| f == field)
            .map(|(_, p)| p.as_path())
    }
}

/// `timeout_ms` and `preset` are campaign fields; the same in `[scenario]` would be ambiguous.
fn reject_overridden(raw: &toml::Table) -> Result<(), SpecError> {
    let scenario = raw.get("scenario").and_then(|s| s.as_table());
    if scenario.is_some_and(|s| s.contains_key("timeout_ms")) {
        return Err(error(
            "scenario.timeout_ms",
            "set timeout_ms at the top level of the campaign",
        ));
    }
    let network = scenario
        .and_then(|s| s.get("network"))
        .and_then(|n| n.as_table());
    if network.is_some_and(|n| n.contains_key("preset")) {
        return Err(error(
            "scenario.network.preset",
            "set preset at the top level of the campaign",
        ));
    }
    Ok(())
}

impl Sweep {
    fn check(&self) -> Result<(), SpecError> {
        if self.loss.is_none()
            && self.dead_link_p.is_none()
            && self.reset_probability.is_none()
            && self.combined.is_none()
        {
            return Err(error(
                "sweep",
                "no axis to sweep: give loss, dead_link_p, reset_probability or combined",
            ));
        }
        let axes = [
            ("sweep.loss", &self.loss),
            ("sweep.dead_link_p", &self.dead_link_p),
            ("sweep.reset_probability", &self.reset_probability),
            ("sweep.combined", &self.combined),
        ];
        for (field, range) in axes {
            if let Some(r) = range {
                r.values(field)?;
            }
        }
        probability("sweep.dead_background_loss", self.dead_background_loss)?;
        probability("sweep.dead_loss", self.dead_loss)?;
        self.check_combined()?;
        match (&self.reset_probability, self.reset_interval_ms) {
            (Some(_), None) => Err(error(
                "sweep.reset_interval_ms",
                "required with reset_probability",
            )),
            (_, Some(0)) => Err(error("sweep.reset_interval_ms", "must be above 0")),
            (None, Some(_)) => Err(error(
                "sweep.reset_interval_ms",
                "given without reset_probability",
            )),
            _ => Ok(()),
        }
    }
}

impl Sweep {
    fn check_combined(&self) -> Result<(), SpecError> {
        let parts = [
            ("sweep.combined_loss", self.combined_loss),
            ("sweep.combined_dead_link_p", self.combined_dead_link_p),
            (
                "sweep.combined_reset_probability",
                self.combined_reset_probability,
            ),
        ];
        for (field, value) in parts {
            match (self.combined.is_some(), value) {
                (true, None) => return Err(error(field, "required with combined")),
                (false, Some(_)) => return Err(error(field, "given without combined")),
                _ => probability(field, value)?,
            }
        }
        match (self.combined.is_some(), self.combined_reset_interval_ms) {
            (false, Some(_)) => Err(error(
                "sweep.combined_reset_interval_ms",
                "given without combined",
            )),
            (_, Some(0)) => Err(error("sweep.combined_reset_interval_ms", "must be above 0")),
            _ => Ok(()),
        }
    }
}

fn probability(field: &str, p: Option<f64>) -> Result<(), SpecError> {
    match p {
        Some(p) if !(0.0..=1.0).contains(&p) => {
            Err(error(field, format!("{p} is not a probability (0 to 1)")))
        }
        _ => Ok(()),
    }
}

impl Range {
    /// The values from `from` to `to` (included, within a millionth of a step) by `step`,
    /// rounded to 9 decimals so that 0.1 + 0.05 is written 0.15. All are probabilities.
    pub fn values(&self, field: &str) -> Result<Vec<f64>, SpecError> {
        if !(self.step > 0.0 && self.step.is_finite()) {
            return Err(error(&format!("{field}.step"), "must be above 0"));
        }
        if self.from.is_nan() || self.to.is_nan() || self.to < self.from {
            return Err(error(&format!("{field}.to"), "must not be below from"));
        }
        let count = ((self.to - self.from) / self.step + 1e-6).floor() + 1.0;
        if count > MAX_POINTS_PER_AXIS as f64 {
            return Err(error(
                &format!("{field}.step"),
                format!("more than {MAX_POINTS_PER_AXIS} points"),
            ));
        }
        let values: Vec<f64> = (0..count as usize)
            .map(|i| ((self.from + i as f64 * self.step) * 1e9).round() / 1e9)
            .collect();
        for v in &values {
            probability(field, Some(*v))?;
        }
        Ok(values)
    }
}

impl ProtocolOptions {
    /// `retries` within `--retries`' range, and only with the retry policy.
    fn check(&self) -> Result<(), SpecError> {
        let Some(n) = self.retries else {
            return Ok(());
        };
        if n > MAX_RETRIES {
            let message = format!("{n} retries is more than {MAX_RETRIES}, the most there may be");
            return Err(error("options.retries", message));
        }
        if self.on_failure == Some(OnFailure::Stop) {
            let message = "retries apply to on_failure = \"retry\"; \"stop\" retries nothing";
            return Err(error("options.retries", message));
        }
        Ok(())
    }
}

/// Protocol options, as `dynarole simulate`'s flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ProtocolOptions {
    /// The paper protocol's merge function (`dynarole simulate --merge`).
    #[serde(deserialize_with = "choice::deserialize")]
    pub merge: PaperMerge,
    pub single_step_handover: bool,
    pub restart_pending: bool,
    pub no_nv: bool,
    /// The lattice protocol's failure policy (`dynarole simulate --on-failure`); none: the
    /// runtime's default.
    #[serde(deserialize_with = "choice::deserialize_some")]
    pub on_failure: Option<OnFailure>,
    /// Times a failed operation is issued again (`--retries`, 0 to 100); none: the runtime's
    /// default.
    pub retries: Option<u8>,
}
