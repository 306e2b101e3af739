//! Reading the files users give dynarole (sources, plugins, configurations, scenarios,
//! campaigns, recordings): the one place that bounds their size and names the file in its
//! errors. It sits below every crate, so the commands that do not simulate (`check`,
//! `compile`, `verify`) read their inputs without linking the simulator.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest input file read (program, plugin, configuration, scenario, campaign, recording).
pub const MAX_INPUT_BYTES: u64 = 8 << 20;

/// A user's file that could not be read: which file, and why.
#[derive(Debug)]
pub struct InputError {
    pub path: PathBuf,
    pub error: std::io::Error,
}

impl fmt::Display for InputError {
    /// `cannot read FILE: REASON`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot read {}: {}", self.path.display(), self.error)
    }
}

impl std::error::Error for InputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.error)
    }
}

/// Reads a user's file as text; the error names the file.
pub fn read_input(path: &Path) -> Result<String, InputError> {
    read_limited(path).map_err(|error| InputError {
        path: path.to_path_buf(),
        error,
    })
}

/// Reads a user's file as text, refusing one larger than [`MAX_INPUT_BYTES`] (or endless,
/// like `/dev/zero`) after reading no more than that, or one that is not UTF-8.
pub fn read_limited(path: &Path) -> std::io::Result<String> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        let message = format!(
            "the file is larger than {} MiB, the limit for input files",
            MAX_INPUT_BYTES >> 20
        );
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let message = format!("the file is not UTF-8 text (byte {at})");
        std::io::Error::new(std::io::ErrorKind::InvalidData, message)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str, bytes: &[u8]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("dynarole-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch dir");
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("scratch file");
        path
    }

    #[test]
    fn reads_text() {
        let path = scratch("ok.dr", b"robot atron;\n");
        assert_eq!(read_input(&path).expect("read"), "robot atron;\n");
    }

    #[test]
    fn errors_name_the_file() {
        let path = scratch("bad.dr", b"ok\xff");
        let e = read_input(&path).expect_err("not UTF-8");
        let text = e.to_string();
        assert!(
            text.starts_with(&format!("cannot read {}: ", path.display())),
            "{text}"
        );
        assert!(
            text.ends_with("the file is not UTF-8 text (byte 2)"),
            "{text}"
        );
        let missing = read_input(&path.with_file_name("missing.dr")).expect_err("missing");
        assert_eq!(missing.error.kind(), std::io::ErrorKind::NotFound);
        assert!(missing.to_string().contains("missing.dr"));
    }

    #[test]
    fn refuses_more_than_the_limit() {
        let limit = usize::try_from(MAX_INPUT_BYTES).expect("fits");
        let at_limit = scratch("at-limit.json", &vec![b' '; limit]);
        assert_eq!(read_limited(&at_limit).expect("at the limit").len(), limit);
        let over = scratch("over.json", &vec![b' '; limit + 1]);
        let e = read_limited(&over).expect_err("over the limit");
        assert!(e.to_string().contains("larger than 8 MiB"), "{e}");
    }
}
