//! Reading the files users give dynarole (sources, plugins, configurations, scenarios,
//! campaigns, recordings): the one place that bounds their size and names the file in its
//! errors, and the one loader of robot plugin files (`program.rs`). It sits below every crate
//! but the core, so the commands that do not simulate (`check`, `compile`, `verify`) read
//! their inputs without linking the simulator.

pub mod program;

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest input file read (program, plugin, configuration, scenario, campaign, shard).
pub const MAX_INPUT_BYTES: u64 = 8 << 20;

/// Largest recording read (`dynarole view`) and written (`--record`, `--html`): one limit for
/// both, so that every recording a command writes can be viewed. A recording holds at most a
/// million trace lines and packets (the simulator's bound), which fits.
pub const MAX_RECORDING_BYTES: u64 = 256 << 20;

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

/// A recording as [`read_input`] reads any file, up to [`MAX_RECORDING_BYTES`].
pub fn read_recording(path: &Path) -> Result<String, InputError> {
    read_up_to(path, MAX_RECORDING_BYTES).map_err(|error| InputError {
        path: path.to_path_buf(),
        error,
    })
}

/// Reads a user's file as text, refusing one larger than [`MAX_INPUT_BYTES`] (or endless,
/// like `/dev/zero`) after reading no more than that, or one that is not UTF-8.
pub fn read_limited(path: &Path) -> std::io::Result<String> {
    read_up_to(path, MAX_INPUT_BYTES)
}

/// The bounded read itself. Only a regular file is opened: a FIFO would block the open or the
/// read for ever, and a device may never end.
fn read_up_to(path: &Path, limit: u64) -> std::io::Result<String> {
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        let what = if kind.is_dir() {
            "a directory"
        } else {
            "not a regular file"
        };
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{what}; expected a regular file"),
        ));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(limit + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        let message = format!(
            "the file is larger than {} MiB, the limit for such files",
            limit >> 20
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

    /// A file in a directory removed when the test ends (some are 8 MiB).
    fn scratch(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> PathBuf {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("scratch file");
        path
    }

    #[test]
    fn reads_text() {
        let dir = tempfile::tempdir().expect("scratch dir");
        let path = scratch(&dir, "ok.dr", b"robot snakebot;\n");
        assert_eq!(read_input(&path).expect("read"), "robot snakebot;\n");
    }

    #[test]
    fn errors_name_the_file() {
        let dir = tempfile::tempdir().expect("scratch dir");
        let path = scratch(&dir, "bad.dr", b"ok\xff");
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
        let dir = tempfile::tempdir().expect("scratch dir");
        let limit = usize::try_from(MAX_INPUT_BYTES).expect("fits");
        let at_limit = scratch(&dir, "at-limit.json", &vec![b' '; limit]);
        assert_eq!(read_limited(&at_limit).expect("at the limit").len(), limit);
        let over = scratch(&dir, "over.json", &vec![b' '; limit + 1]);
        let e = read_limited(&over).expect_err("over the limit");
        assert!(e.to_string().contains("larger than 8 MiB"), "{e}");
    }

    #[test]
    fn refuses_what_is_not_a_regular_file() {
        let dir = tempfile::tempdir().expect("scratch dir");
        let sub = scratch(&dir, "dir-probe", b"").with_file_name("a-directory");
        std::fs::create_dir_all(&sub).expect("dir");
        let e = read_input(&sub).expect_err("a directory");
        assert!(
            e.to_string()
                .contains("a directory; expected a regular file"),
            "{e}"
        );
        // Endless: once read until the memory ran out.
        let e = read_input(Path::new("/dev/zero")).expect_err("a device");
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn refuses_a_fifo_without_blocking() {
        let dir = tempfile::tempdir().expect("scratch dir");
        // Opening a FIFO with no writer blocks for ever: it must never be opened.
        let fifo = scratch(&dir, "fifo-probe", b"").with_file_name("a-fifo");
        let _ = std::fs::remove_file(&fifo);
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("skipped: mkfifo is not available");
            return;
        }
        let e = read_input(&fifo).expect_err("a FIFO");
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }

    #[test]
    fn a_recording_may_be_larger_than_other_inputs() {
        let dir = tempfile::tempdir().expect("scratch dir");
        let limit = usize::try_from(MAX_INPUT_BYTES).expect("fits");
        let large = scratch(&dir, "large-recording.json", &vec![b' '; limit + 1]);
        assert_eq!(
            read_recording(&large).expect("within its limit").len(),
            limit + 1
        );
    }
}
