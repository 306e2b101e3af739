//! The corpus on disk: `fuzz/corpus/<target>/` (run by every test) and
//! `fuzz/regressions/<target>/` (hostile inputs kept as regression cases).

use std::path::{Path, PathBuf};

/// Largest corpus file: mutations copy and repeat parts of files, so large seeds would make
/// every case slow without finding more.
pub const MAX_ENTRY_BYTES: usize = 16 * 1024;

/// One corpus file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The file name, to report which input failed.
    pub name: String,
    pub bytes: Vec<u8>,
}

impl Entry {
    /// The text a target sees (loaders take `&str`; invalid UTF-8 is replaced, as the CLI's
    /// readers would refuse it before any loader runs).
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.bytes).into_owned()
    }
}

/// The files of one corpus folder, sorted by name so runs are deterministic.
#[derive(Clone, Debug, Default)]
pub struct Corpus {
    pub entries: Vec<Entry>,
}

/// The repository's `fuzz/` folder.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz")
}

impl Corpus {
    /// Reads every file of `dir` (not recursing). A missing folder is an empty corpus; an
    /// unreadable or oversized file is an error naming it.
    pub fn load(dir: &Path) -> Result<Corpus, String> {
        if !dir.exists() {
            return Ok(Corpus::default());
        }
        let listing =
            std::fs::read_dir(dir).map_err(|e| format!("{}: cannot list: {e}", dir.display()))?;
        let mut paths = Vec::new();
        for item in listing {
            let path = item
                .map_err(|e| format!("{}: cannot list: {e}", dir.display()))?
                .path();
            if path.is_file() {
                paths.push(path);
            }
        }
        paths.sort();
        let entries = paths
            .iter()
            .map(|p| read_entry(p))
            .collect::<Result<_, _>>()?;
        Ok(Corpus { entries })
    }
}

fn read_entry(path: &Path) -> Result<Entry, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    if bytes.len() > MAX_ENTRY_BYTES {
        return Err(format!(
            "{}: {} bytes, expected at most {MAX_ENTRY_BYTES} (keep corpus files small)",
            path.display(),
            bytes.len()
        ));
    }
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Entry { name, bytes })
}
