//! Reading inputs: source files and robot plugins, with errors that name the file.

use dynarole_core::robot::RobotApi;
use dynarole_core::RobotRegistry;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A command that could not run; printed as `error: ...` by `main`.
#[derive(Debug)]
pub enum Failure {
    /// Bad input (exit 1).
    Input(String),
    /// Bad usage (exit 2).
    Usage(String),
}

impl Failure {
    pub fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Input(_) => ExitCode::from(1),
            Failure::Usage(_) => ExitCode::from(2),
        }
    }

    pub fn message(&self) -> &str {
        match self {
            Failure::Input(m) | Failure::Usage(m) => m,
        }
    }
}

#[derive(clap::Args, Clone, Debug, Default)]
pub struct PluginArgs {
    /// Load a robot API plugin (TOML); may be repeated. A file `NAME.robot.toml` beside the
    /// source is loaded automatically when the source says `robot NAME;`.
    #[arg(long = "plugin", value_name = "FILE")]
    pub plugins: Vec<PathBuf>,
}

/// Every user file the commands read comes through here (with the size limit).
pub fn read_source(path: &Path) -> Result<String, Failure> {
    dynarole_campaign::read_limited(path)
        .map_err(|e| Failure::Input(format!("cannot read {}: {e}", path.display())))
}

/// Built-in robots, then `--plugin` files, then a `NAME.robot.toml` beside `source_path`
/// for a `robot NAME;` that is still unknown.
pub fn registry(
    args: &PluginArgs,
    source_path: &Path,
    robot_name: Option<&str>,
) -> Result<RobotRegistry, Failure> {
    let mut registry = RobotRegistry::builtin();
    for path in &args.plugins {
        registry.add(load_plugin(path)?);
    }
    if let Some(name) = robot_name {
        let beside = source_path.with_file_name(format!("{name}.robot.toml"));
        if registry.get(name).is_none() && beside.is_file() {
            registry.add(load_plugin(&beside)?);
        }
    }
    Ok(registry)
}

fn load_plugin(path: &Path) -> Result<RobotApi, Failure> {
    let text = read_source(path)?;
    RobotApi::from_toml(&text).map_err(|e| Failure::Input(format!("{}: {e}", path.display())))
}

/// The name in the file's first `robot NAME;`, if any.
pub fn robot_name(file: &dynarole_core::ast::SourceFile) -> Option<&str> {
    file.items.iter().find_map(|item| match item {
        dynarole_core::ast::Item::Robot(decl) => Some(decl.name.name.as_str()),
        _ => None,
    })
}

/// Reads, parses and checks a source file: renders its errors and exits 1, or hands the checked
/// program and its text to `then` (every command that works on a checked file starts here).
pub fn with_program(
    path: &Path,
    plugins: &PluginArgs,
    then: impl FnOnce(&dynarole_core::Program, &str) -> Result<ExitCode, Failure>,
) -> Result<ExitCode, Failure> {
    let source = read_source(path)?;
    let parsed = dynarole_core::parse(&source);
    let registry = registry(plugins, path, robot_name(&parsed.file))?;
    let (program, mut diagnostics) = dynarole_core::analyze(&parsed.file, &registry);
    diagnostics.extend(parsed.diagnostics);
    diagnostics.sort_by_key(|d| d.span);
    match program.filter(|_| !dynarole_core::diagnostic::has_errors(&diagnostics)) {
        Some(program) => then(&program, &source),
        None => {
            crate::render::diagnostics(&path.display().to_string(), &source, &diagnostics);
            Ok(ExitCode::from(1))
        }
    }
}

/// The named sequences, or the first one the file declares when none is named.
pub fn sequence_names(program: &dynarole_core::Program, sequences: &[String]) -> Vec<String> {
    if !sequences.is_empty() {
        return sequences.to_vec();
    }
    program
        .file
        .sequences()
        .next()
        .map(|d| d.name.name.clone())
        .into_iter()
        .collect()
}
