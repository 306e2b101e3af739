//! A command that could not run, and the exit code it ends with (the codes of README.md).

use dynarole_core::toml_error::TomlError;
use std::path::Path;
use std::process::ExitCode;

/// A command that could not run; printed as `error: ...` by `main`.
#[derive(Debug)]
pub enum Failure {
    /// Bad input (exit 1).
    Input(String),
    /// Bad usage (exit 2).
    Usage(String),
    /// A TOML file (plugin, scenario, campaign) with an error (exit 1), shown with its snippet.
    Toml {
        path: String,
        text: String,
        error: Box<TomlError>,
    },
    /// A `.dr` file the checks refused (exit 1): its diagnostics, rendered with its text by
    /// the command line, handed over as data by the library API (`api.rs`).
    Checked {
        path: String,
        source: String,
        diagnostics: Vec<dynarole_core::Diagnostic>,
        /// What the command concludes from them, printed after them as `error: ...`.
        conclusion: Option<String>,
    },
    /// A failure of dynarole or of the tools it runs (spin, the C compiler), not a verdict on
    /// the input (exit 4).
    Internal(String),
}

/// The exit code of an internal failure (0-3 are verdicts and usage errors).
pub const INTERNAL_EXIT: u8 = 4;

impl Failure {
    pub fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Input(_) | Failure::Toml { .. } | Failure::Checked { .. } => ExitCode::from(1),
            Failure::Usage(_) => ExitCode::from(2),
            Failure::Internal(_) => ExitCode::from(INTERNAL_EXIT),
        }
    }

    /// The refusal of the `.dr` file `path` (text `source`) for `diagnostics`.
    pub fn checked(
        path: &str,
        source: &str,
        diagnostics: Vec<dynarole_core::Diagnostic>,
    ) -> Failure {
        Failure::Checked {
            path: path.to_string(),
            source: source.to_string(),
            diagnostics,
            conclusion: None,
        }
    }

    /// The same refusal, concluded by `message` after the diagnostics.
    pub fn concluded(self, message: String) -> Failure {
        match self {
            Failure::Checked {
                path,
                source,
                diagnostics,
                ..
            } => Failure::Checked {
                path,
                source,
                diagnostics,
                conclusion: Some(message),
            },
            other => other,
        }
    }

    /// The failure of the TOML file at `path`, whose text is `text`.
    pub fn toml(path: &Path, text: String, error: TomlError) -> Failure {
        Failure::Toml {
            path: path.display().to_string(),
            error: Box::new(error.locate(&text)),
            text,
        }
    }
}
