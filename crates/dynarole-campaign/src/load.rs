//! Reading a campaign's inputs: the campaign file, the `.dr` program (built-in robots, the
//! campaign's plugins, and a `NAME.robot.toml` beside the source), the sequences'
//! plans and the configurations.

use crate::inputs::Fingerprint;
use crate::spec::{CampaignFile, SpecError};
use crate::Error;
use dynarole_codegen::{CompileOptions, Variant};
use dynarole_core::driver::{self, SelectError};
use dynarole_core::expand::Plan;
use dynarole_core::Program;
use dynarole_input::program::{self, PluginError};
use dynarole_sim::Preset;
use dynarole_world::{Configuration, Robots};
use std::path::Path;

/// The files a campaign reads, parsed (the program borrows the syntax tree from here).
pub struct Sources {
    pub path: std::path::PathBuf,
    /// The campaign file's text (errors found later point into it).
    pub text: String,
    pub campaign: CampaignFile,
    pub source: String,
    /// The program's syntax tree and its syntax errors.
    pub parsed: dynarole_core::Parsed,
    pub start: Configuration,
    pub expect: Option<Configuration>,
    /// The files read so far (the campaign file, the program, the configurations).
    pub fingerprint: Fingerprint,
    /// The robot kinds the configurations and the program may be of.
    pub robots: Robots,
}

/// Everything the runs share (all `Sync`: each worker builds its own simulators from it).
pub struct Inputs<'a> {
    pub campaign: &'a CampaignFile,
    pub source: &'a str,
    pub program: Program<'a>,
    pub plans: Vec<Plan>,
    pub start: &'a Configuration,
    pub expect: Option<&'a Configuration>,
    /// The network preset of every run (the campaign's `preset` among the robot's).
    pub preset: Preset,
    /// Every file the runs are computed from, the robot plugins included.
    pub fingerprint: Fingerprint,
}

/// Every file a campaign names is read through `dynarole_input` (the size limit); the error
/// names the file as the campaign's other errors do.
fn read(path: &Path) -> Result<String, Error> {
    dynarole_input::read_input(path).map_err(|e| Error::io(&e.path, e.error))
}

/// Reads the file that the campaign's `field` names (resolved to `path`); an error points at
/// the field in the campaign file and says, for a relative path, what it was relative to.
fn read_field(
    campaign_path: &Path,
    text: &str,
    campaign: &CampaignFile,
    field: &str,
    path: &Path,
) -> Result<String, Error> {
    dynarole_input::read_input(path).map_err(|e| {
        let written = campaign.written(field).unwrap_or(path);
        let mut error = SpecError::new(
            field,
            format!("cannot read \"{}\": {}", written.display(), e.error),
        );
        if written.is_relative() {
            let dir = campaign_path.parent().unwrap_or(Path::new("."));
            error.hint = Some(format!(
                "a relative path in a campaign file is relative to the campaign file's \
                 directory ({}), not to where dynarole runs: \"{}\" resolved to {}",
                if dir.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    dir
                }
                .display(),
                written.display(),
                path.display()
            ));
        }
        Error::Spec {
            path: campaign_path.to_path_buf(),
            text: text.to_string(),
            error: Box::new(error.locate(text)),
        }
    })
}

/// Reads the campaign file and everything it names, its configurations of one of `robots`.
pub fn sources(path: &Path, robots: &Robots) -> Result<Sources, Error> {
    let text = read(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let campaign = CampaignFile::parse(&text, dir).map_err(|e| Error::Spec {
        path: path.to_path_buf(),
        text: text.clone(),
        error: Box::new(e),
    })?;
    let mut fingerprint = Fingerprint::new();
    fingerprint.add("campaign", path, &text);
    let field = |name: &str, file: &Path| read_field(path, &text, &campaign, name, file);
    let source = field("file", &campaign.file)?;
    fingerprint.add("program", &campaign.file, &source);
    let parsed = dynarole_core::parse(&source);
    let from = field("from", &campaign.from)?;
    let start = configuration(robots, &campaign.from, &from, &mut fingerprint, "from")?;
    let expect = match campaign.expect.as_deref() {
        Some(p) => Some(configuration(
            robots,
            p,
            &field("expect", p)?,
            &mut fingerprint,
            "expect",
        )?),
        None => None,
    };
    Ok(Sources {
        fingerprint,
        path: path.to_path_buf(),
        text,
        campaign,
        source,
        parsed,
        start,
        expect,
        robots: robots.clone(),
    })
}

/// Checks the program and expands its sequences.
pub fn inputs(sources: &Sources) -> Result<Inputs<'_>, Error> {
    let campaign = &sources.campaign;
    let mut fingerprint = sources.fingerprint.clone();
    let program = program(sources, &mut fingerprint)?;
    let plans = dynarole_core::driver::plans(&program, &campaign.sequences)
        .map_err(|e| unknown_sequence(sources, &e))?;
    // A module the program names but the start lacks would never act: every run would only
    // time out. Refused here, before anything is written (run, --emit, status alike).
    dynarole_replay::assign_modules(&program, &plans, &sources.start).map_err(|diagnostics| {
        Error::Diagnostics {
            path: campaign.file.clone(),
            source: sources.source.clone(),
            diagnostics,
        }
    })?;
    let spec_error = |error: SpecError| Error::Spec {
        path: sources.path.clone(),
        error: Box::new(error.locate(&sources.text)),
        text: sources.text.clone(),
    };
    let presets = sources.start.kind().network_presets();
    let preset = (campaign.scenario.network.preset.resolve(presets))
        .map_err(|message| spec_error(SpecError::new("preset", message)))?;
    // Every run would fail on an unknown timing preset: refused here, at its field.
    (campaign.scenario.timing.durations(&program.robot))
        .map_err(|e| spec_error(e.nested_in("scenario")))?;
    Ok(Inputs {
        campaign,
        source: &sources.source,
        program,
        plans,
        start: &sources.start,
        preset,
        expect: sources.expect.as_ref(),
        fingerprint,
    })
}

/// A sequence the campaign names that the program lacks: the field `sequences[i]`, with the
/// closest name and the program's list.
fn unknown_sequence(sources: &Sources, e: &SelectError) -> Error {
    let file = sources.campaign.file.display().to_string();
    let (field, message) = match e {
        SelectError::Unknown { index, name, .. } => (
            format!("sequences[{index}]"),
            format!("no sequence `{name}` in {file}"),
        ),
        SelectError::NoSequence => ("sequences".to_string(), e.message(&file)),
    };
    let mut error = SpecError::new(field, message);
    error.hint = Some(e.detail(&file));
    Error::Spec {
        path: sources.path.clone(),
        error: Box::new(error.locate(&sources.text)),
        text: sources.text.clone(),
    }
}

/// The configuration read from `path` as `text`, recorded in `fingerprint` as `role`.
fn configuration(
    robots: &Robots,
    path: &Path,
    text: &str,
    fingerprint: &mut Fingerprint,
    role: &str,
) -> Result<Configuration, Error> {
    fingerprint.add(role, path, text);
    (robots.read_configuration(text)).map_err(|e| Error::Input(format!("{}: {e}", path.display())))
}

/// The checked program; every plugin it loads (through `dynarole_input::program`, the
/// commands' loader too) is recorded in `fingerprint`.
fn program<'a>(sources: &'a Sources, fingerprint: &mut Fingerprint) -> Result<Program<'a>, Error> {
    let campaign = &sources.campaign;
    let mut plugins = Vec::new();
    for (i, path) in campaign.plugins.iter().enumerate() {
        let field = format!("plugins[{i}]");
        let text = read_field(&sources.path, &sources.text, campaign, &field, path)?;
        fingerprint.add("plugin", path, &text);
        plugins.push(program::plugin(path, text).map_err(plugin_error)?);
    }
    let robot = driver::robot_name(&sources.parsed.file);
    let mut seen = |path: &Path, text: &str| fingerprint.add("plugin", path, text);
    let built_in = dynarole_robots::plugins_of(&sources.robots).map_err(Error::Input)?;
    let registry = program::registry(built_in, &campaign.file, robot, plugins, &mut seen)
        .map_err(plugin_error)?;
    driver::check(&sources.parsed, &registry).map_err(|diagnostics| Error::Diagnostics {
        path: campaign.file.clone(),
        source: sources.source.clone(),
        diagnostics,
    })
}

/// A plugin that cannot be read names the file, as any unreadable file of a campaign; one that
/// is not a plugin is an error in its TOML.
fn plugin_error(error: PluginError) -> Error {
    match error {
        PluginError::Read(e) => Error::io(&e.path, e.error),
        PluginError::Invalid { path, text, error } => Error::Spec { path, text, error },
    }
}

/// The back-end's options for `protocol` and the campaign's `[options]`.
pub fn compile_options(campaign: &CampaignFile, protocol: Variant) -> CompileOptions {
    let o = &campaign.options;
    CompileOptions {
        protocol: protocol.protocol(),
        merge: o.merge,
        single_step_handover: o.single_step_handover,
        restart_pending: o.restart_pending,
        epochs: 1,
        no_nv: o.no_nv,
        dissemination: protocol.dissemination(),
        token_retries: protocol.token_retries(),
        routes: None,
        name: campaign.sequences.join(" + "),
        ..failure_policy(o)
    }
}

/// The default options with the campaign's failure policy, where it names one.
fn failure_policy(o: &crate::spec::ProtocolOptions) -> CompileOptions {
    let defaults = CompileOptions::default();
    CompileOptions {
        on_failure: o.on_failure.unwrap_or(defaults.on_failure),
        retries: o.retries.unwrap_or(defaults.retries),
        ..defaults
    }
}

#[cfg(test)]
mod dissemination_tests {
    use super::*;
    use dynarole_codegen::{Dissemination, Protocol};

    /// `lattice-fixed` is the lattice protocol with the fixed period (its name is checked
    /// against the mode's in the protocol table); `lattice` is adaptive, like the command
    /// line's default.
    #[test]
    fn lattice_fixed_selects_the_fixed_dissemination() {
        let campaign: CampaignFile = toml::from_str(
            "file = \"a.dr\"\nsequences = [\"s\"]\nfrom = \"a.json\"\nprotocols = [\"lattice\", \"lattice-fixed\"]\nseeds = 1\n",
        )
        .expect("parses");
        let fixed = compile_options(&campaign, Variant::LatticeFixed);
        assert_eq!(
            (fixed.protocol, fixed.dissemination),
            (Protocol::Lattice, Dissemination::Fixed)
        );
        let adaptive = compile_options(&campaign, Variant::Lattice);
        assert_eq!(adaptive.dissemination, Dissemination::Adaptive);
    }
}
