//! Reading the campaign's own files back (shard results, `runs.csv`, the copies kept in an
//! output directory) with a bound, and only from regular files: a FIFO would block `merge`
//! and `status` forever, a link to `/dev/zero` would fill the memory, and a dangling link
//! is not a missing shard.

use crate::Error;
use std::io::Read;
use std::path::Path;

/// The most bytes one row of a results file takes: 23 columns, the longest an integer (20
/// digits), a float (24 characters) or a name; a row of this size is already far longer
/// than any real one (about 150 bytes).
pub const MAX_ROW_BYTES: u64 = 1024;

/// What the lines before a results file's header may take (the record of its inputs: a hash
/// and a path per input).
pub const MAX_PREAMBLE_BYTES: u64 = 1 << 20;

/// The most bytes a results file of `runs` rows (plus a header and a last row cut short)
/// may hold.
pub fn results_bound(runs: u64) -> u64 {
    MAX_PREAMBLE_BYTES + runs.saturating_add(2).saturating_mul(MAX_ROW_BYTES)
}

/// The text of `path`, or `None` when there is no such file; an error (naming the file) when
/// it is a dangling link, not a regular file, larger than `limit` bytes (read no further)
/// or not UTF-8.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Option<String>, Error> {
    let bad = |why: String| Error::Results(format!("{}: {why}", path.display()));
    if !regular(path)? {
        return Ok(None);
    }
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // Checked again on the open file: the path may have been replaced in between.
    let opened = file.metadata().map_err(|e| Error::io(path, e))?;
    if !opened.is_file() {
        return Err(bad("not a regular file".into()));
    }
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(bad(format!(
            "larger than {limit} bytes, more than its runs can fill; it is not a file this \
             campaign wrote"
        )));
    }
    String::from_utf8(bytes).map(Some).map_err(|e| {
        bad(format!(
            "not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// Whether `path` is a regular file (false: nothing is there); an error naming it when it is
/// a dangling link or anything but a file (checked without opening it: opening a FIFO
/// blocks).
pub fn regular(path: &Path) -> Result<bool, Error> {
    let bad = |why: String| Error::Results(format!("{}: {why}", path.display()));
    let link = match std::fs::symlink_metadata(path) {
        Ok(m) => m.file_type().is_symlink(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(Error::io(path, e)),
    };
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if link && e.kind() == std::io::ErrorKind::NotFound => {
            let target = std::fs::read_link(path).map_or("?".into(), |t| t.display().to_string());
            return Err(bad(format!(
                "a dangling link (to {target}, which does not exist); remove it or restore \
                 its target"
            )));
        }
        Err(e) => return Err(Error::io(path, e)),
    };
    if !meta.is_file() {
        return Err(bad(format!(
            "not a regular file ({}); results and copies in an output directory must be files",
            kind(&meta.file_type())
        )));
    }
    Ok(true)
}

/// What a file that is not a regular file is, in words.
fn kind(file_type: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    if file_type.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

/// Writes `text` to `path` through a temporary file renamed into place (many shards may
/// start at once; a reader sees the old file or the new one).
pub fn write_atomically(path: &Path, text: &str) -> Result<(), Error> {
    let name = path
        .file_name()
        .map_or("file".into(), |n| n.to_string_lossy().into_owned());
    let temp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    std::fs::write(&temp, text).map_err(|e| Error::io(&temp, e))?;
    std::fs::rename(&temp, path).map_err(|e| Error::io(path, e))
}
