//! Campaigns split over many processes or machines: shard K of N holds the runs whose index
//! is K modulo N (the split depends only on the plan and N, and each run keeps its seed), and
//! writes `shard-K-of-N.csv` in the output directory beside a copy of the campaign file;
//! `merge` checks that every run is there exactly once and writes the outputs of a
//! one-machine run, `status` counts the runs done so far.

use crate::files;
use crate::inputs::{hash_text, Fingerprint, INPUTS_FILE};
use crate::plan::Plan;
use crate::results::{self, Row};
use crate::spec::CampaignFile;
use crate::Error;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Most shards a campaign may be split into (more would be files of a few runs each).
pub const MAX_SHARDS: u64 = 100_000;

/// The copy of the campaign file that every shard writes and `merge` and `status` read.
pub const CAMPAIGN_COPY: &str = "campaign.toml";

/// Shard `index` (from 0) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `K/N`, with 0 <= K < N <= [`MAX_SHARDS`].
    fn from_str(text: &str) -> Result<Shard, String> {
        let expected = || format!("`{text}`: expected K/N, shard K (from 0) of N, like 3/8");
        let (k, n) = text.split_once('/').ok_or_else(expected)?;
        let index: u64 = k.trim().parse().map_err(|_| expected())?;
        let count: u64 = n.trim().parse().map_err(|_| expected())?;
        if count == 0 || count > MAX_SHARDS {
            return Err(format!("`{text}`: N must be 1 to {MAX_SHARDS}"));
        }
        if index >= count {
            return Err(format!(
                "`{text}`: shards are numbered 0 to {} (like Slurm's array tasks)",
                count - 1
            ));
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether run `run` belongs to this shard (runs are dealt out in turn, so that every
    /// shard gets its share of the slow, high-fault runs).
    pub fn holds(self, run: u64) -> bool {
        run % self.count == self.index
    }

    /// The number of runs of a plan of `total` runs in this shard.
    pub fn size(self, total: u64) -> u64 {
        total / self.count + u64::from(self.index < total % self.count)
    }

    /// The results file once every run of the shard is done.
    pub fn file_name(self) -> String {
        format!("shard-{}-of-{}.csv", self.index, self.count)
    }

    /// The results file while the shard runs (appended to; resumed from).
    pub fn partial_name(self) -> String {
        format!("{}.partial", self.file_name())
    }

    /// The shard whose finished or partial results file is named `name`.
    fn of_file_name(name: &str) -> Option<(Shard, bool)> {
        let (stem, finished) = match name.strip_suffix(".partial") {
            Some(stem) => (stem, false),
            None => (name, true),
        };
        let (k, n) = stem
            .strip_prefix("shard-")?
            .strip_suffix(".csv")?
            .split_once("-of-")?;
        let shard: Shard = format!("{k}/{n}").parse().ok()?;
        (shard.file_name() == stem).then_some((shard, finished))
    }
}

/// The results files of one split found in a directory.
#[derive(Debug, Default)]
pub struct Found {
    /// N, if any shard file is there.
    pub count: Option<u64>,
    /// By shard index: (finished file, partial file), each if present.
    pub files: BTreeMap<u64, (Option<PathBuf>, Option<PathBuf>)>,
}

/// The shard files in `dir`; an error when they belong to two different splits.
pub fn find(dir: &Path) -> Result<Found, Error> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut found = Found::default();
    let mut strange = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some((shard, finished)) = Shard::of_file_name(&name) else {
            // A name like a shard file's that no shard has (shard-9-of-8.csv, shard-03-of-8.csv,
            // shard-1-of-8.csv.bak): said, not skipped, since it may hold runs of the split.
            if name.starts_with("shard-") {
                strange.push(entry.path());
            }
            continue;
        };
        if let Some(n) = found.count.filter(|&n| n != shard.count) {
            return Err(Error::Results(format!(
                "{}: holds shards of a split into {n} and into {}; \
                 keep each split in its own directory",
                dir.display(),
                shard.count
            )));
        }
        found.count = Some(shard.count);
        let slot = found.files.entry(shard.index).or_default();
        let path = Some(entry.path());
        if finished {
            slot.0 = path;
        } else {
            slot.1 = path;
        }
    }
    if !strange.is_empty() {
        strange.sort();
        let names: Vec<String> = strange.iter().map(|p| p.display().to_string()).collect();
        return Err(Error::Results(format!(
            "{}: {} named like a shard's results but no shard's (expected \
             shard-K-of-N.csv or shard-K-of-N.csv.partial, 0 <= K < N, no leading zeros): {}; \
             rename or remove {}",
            dir.display(),
            if names.len() == 1 {
                "a file is"
            } else {
                "files are"
            },
            names.join(", "),
            if names.len() == 1 { "it" } else { "them" },
        )));
    }
    Ok(found)
}

/// Writes the campaign file's text into `dir` (atomically: many shards may start at once),
/// or checks that the copy already there is the same text. With no results in `dir` yet
/// (`has_results` false: right after `--emit`, say) a different copy is replaced: no run
/// of it would be mixed with runs of the new one.
pub fn keep_campaign(dir: &Path, text: &str, has_results: bool) -> Result<(), Error> {
    let path = dir.join(CAMPAIGN_COPY);
    match files::read_bounded(&path, crate::MAX_INPUT_BYTES)? {
        Some(there) if there == text => return Ok(()),
        Some(_) if has_results => {
            return Err(Error::Results(format!(
                "{}: the shards in this directory were run from another campaign file \
                 (or it changed since); write to another directory (-o)",
                path.display()
            )))
        }
        _ => {}
    }
    files::write_atomically(&path, text)
}

/// Writes the record of the inputs into `dir` (`campaign.inputs`), or checks that the one
/// there has the same inputs; replaced when `dir` holds no results yet (as the copy of the
/// campaign file). `what` says whose results a mismatch refuses (`the shards in DIR`).
pub fn keep_inputs(
    dir: &Path,
    now: &Fingerprint,
    has_results: bool,
    what: &str,
) -> Result<(), Error> {
    let path = dir.join(INPUTS_FILE);
    let there = files::read_bounded(&path, files::MAX_PREAMBLE_BYTES)?;
    let recorded = there.as_deref().and_then(|t| Fingerprint::parse(t).0);
    if let Some(before) = &recorded {
        let changes = before.changes(now);
        if changes.is_empty() {
            return Ok(());
        }
        if has_results {
            return Err(Error::Results(format!(
                "{}: {what} were computed from other inputs than now: {}; write to \
                 another directory (-o), or remove them to start over",
                path.display(),
                changes.join("; ")
            )));
        }
    } else if has_results {
        return Err(Error::Results(format!(
            "{}: {}; {what} cannot be told apart from runs of other inputs: remove them to \
             start over, or write to another directory (-o)",
            path.display(),
            if there.is_some() {
                "not a record of a campaign's inputs"
            } else {
                "missing"
            }
        )));
    }
    files::write_atomically(&path, &now.to_text())
}

/// The campaign and plan of the shards in `dir` (from the copy of the campaign file).
pub fn campaign_of(dir: &Path) -> Result<(CampaignFile, Plan, String), Error> {
    let path = dir.join(CAMPAIGN_COPY);
    let text = files::read_bounded(&path, crate::MAX_INPUT_BYTES)?.ok_or_else(|| {
        // The system's own words for a missing file.
        let e = std::fs::metadata(&path)
            .err()
            .unwrap_or_else(|| std::io::ErrorKind::NotFound.into());
        Error::Results(format!(
            "{}: {e}; is {} the output directory of `dynarole campaign FILE --shard K/N -o DIR`?",
            path.display(),
            dir.display()
        ))
    })?;
    let spec = |error: crate::SpecError| Error::Spec {
        path: path.clone(),
        error: Box::new(error.locate(&text)),
        text: text.clone(),
    };
    let campaign = CampaignFile::parse(&text, dir).map_err(spec)?;
    let plan = crate::plan::plan(&campaign).map_err(spec)?;
    Ok((campaign, plan, text))
}

/// Every row of a complete split in `dir`, in run order, and the record of the inputs they
/// were all computed from; an error naming the shards run from other inputs, or the missing
/// or unfinished shards and the missing runs.
pub fn merged_rows(dir: &Path) -> Result<(Vec<Row>, Fingerprint), Error> {
    let (campaign, plan, text) = campaign_of(dir)?;
    let found = find(dir)?;
    let count = found.count.ok_or_else(|| {
        Error::Results(format!(
            "{}: no shard results (shard-K-of-N.csv)",
            dir.display()
        ))
    })?;
    let recorded = files::read_bounded(&dir.join(INPUTS_FILE), files::MAX_PREAMBLE_BYTES)?;
    let mut reference = recorded.as_deref().and_then(|t| Fingerprint::parse(t).0);
    let (mut mixed, mut problems, mut rows) = (Vec::new(), Vec::new(), Vec::new());
    for index in 0..count {
        let shard = Shard { index, count };
        match found.files.get(&index) {
            Some((Some(file), _)) => {
                let shard_rows = crate::recorded(file, &plan, (&campaign, None), Some(shard))?;
                let inputs = shard_rows.inputs.as_ref();
                if reference.is_none() {
                    reference = inputs.cloned();
                }
                let against = (reference.as_ref(), text.as_str(), dir);
                mixed.extend(mixed_inputs(shard, file, inputs, against));
                rows.extend(shard_rows.rows);
            }
            Some((None, Some(partial))) => problems.push(format!(
                "shard {shard} is unfinished ({} of {} runs in {}): run it again",
                results::count_complete(partial, files::results_bound(shard.size(plan.len())))?,
                shard.size(plan.len()),
                partial.display()
            )),
            _ => problems.push(format!("shard {shard} is missing: run it")),
        }
    }
    if !mixed.is_empty() {
        return Err(Error::Results(format!(
            "{}: cannot merge, the shards' runs were computed from different inputs:\n  {}",
            dir.display(),
            mixed.join("\n  ")
        )));
    }
    let rows = every_run(dir, rows, plan.len(), problems)?;
    Ok((rows, reference.unwrap_or_default()))
}

/// `rows` in run order when they hold each of the `total` runs and no shard had a problem;
/// else an error with the problems, or the runs missing.
fn every_run(
    dir: &Path,
    mut rows: Vec<Row>,
    total: u64,
    mut problems: Vec<String>,
) -> Result<Vec<Row>, Error> {
    rows.sort_by_key(|r| r.run);
    let missing = missing_runs(&rows, total);
    if !missing.is_empty() && problems.is_empty() {
        problems.push(format!("runs missing: {}", list_runs(&missing)));
    }
    if problems.is_empty() {
        return Ok(rows);
    }
    Err(Error::Results(format!(
        "{}: cannot merge, {} of {total} runs are not recorded:\n  {}",
        dir.display(),
        missing.len(),
        problems.join("\n  ")
    )))
}

/// What makes the runs of a finished shard file differ from the split's: no record of their
/// inputs, another campaign file than `dir`'s copy (`text`), or inputs other than
/// `reference` (the directory's record, else the first shard's).
fn mixed_inputs(
    shard: Shard,
    file: &Path,
    inputs: Option<&Fingerprint>,
    (reference, text, dir): (Option<&Fingerprint>, &str, &Path),
) -> Option<String> {
    let Some(inputs) = inputs else {
        return Some(format!(
            "shard {shard} ({}) holds no record of its inputs (written by an older dynarole?): \
             run it again",
            file.display()
        ));
    };
    if inputs.campaign_hash() != Some(hash_text(text).as_str()) {
        return Some(format!(
            "shard {shard} was run with another campaign file than {}",
            dir.join(CAMPAIGN_COPY).display()
        ));
    }
    let changes = reference.map_or(Vec::new(), |r| r.changes(inputs));
    (!changes.is_empty()).then(|| format!("shard {shard} was run with {}", changes.join("; ")))
}

/// The runs of `0..total` not in `rows` (sorted, each index at most once: `recorded` refuses
/// a run recorded twice in one file, and a run belongs to one shard only).
fn missing_runs(rows: &[Row], total: u64) -> Vec<u64> {
    let mut present = rows.iter().map(|r| r.run).peekable();
    let mut missing = Vec::new();
    for run in 0..total {
        if present.peek() == Some(&run) {
            present.next();
        } else {
            missing.push(run);
        }
    }
    missing
}

/// `3, 11, 19` or, past ten, the first ten and how many more.
fn list_runs(runs: &[u64]) -> String {
    let shown: Vec<String> = runs.iter().take(10).map(u64::to_string).collect();
    match runs.len() {
        0..=10 => shown.join(", "),
        n => format!("{} and {} more", shown.join(", "), n - 10),
    }
}

/// How far a split in a directory is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Status {
    pub total: u64,
    pub shards: Option<u64>,
    /// (shard, runs recorded, runs in the shard, finished) for each shard.
    pub per_shard: Vec<(Shard, u64, u64, bool)>,
}

impl Status {
    pub fn done(&self) -> u64 {
        self.per_shard.iter().map(|s| s.1).sum()
    }
}

/// Counts the runs recorded by the shards in `dir`, reading only (shards may be running).
pub fn status(dir: &Path) -> Result<Status, Error> {
    let (_, plan, _) = campaign_of(dir)?;
    let found = find(dir)?;
    let mut per_shard = Vec::new();
    if let Some(count) = found.count {
        for index in 0..count {
            let shard = Shard { index, count };
            let bound = files::results_bound(shard.size(plan.len()));
            let (done, finished) = match found.files.get(&index) {
                Some((Some(file), _)) => (results::count_complete(file, bound)?, true),
                Some((None, Some(partial))) => (results::count_complete(partial, bound)?, false),
                _ => (0, false),
            };
            per_shard.push((shard, done, shard.size(plan.len()), finished));
        }
    }
    Ok(Status {
        total: plan.len(),
        shards: found.count,
        per_shard,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_from_k_of_n() {
        assert_eq!("3/8".parse(), Ok(Shard { index: 3, count: 8 }));
        assert!("8/8".parse::<Shard>().is_err());
        assert!("0/0".parse::<Shard>().is_err());
        assert!("a/8".parse::<Shard>().is_err());
        assert!("3".parse::<Shard>().is_err());
    }

    #[test]
    fn every_run_is_in_exactly_one_shard_of_the_right_size() {
        for count in [1, 7, 64] {
            let shards: Vec<Shard> = (0..count).map(|index| Shard { index, count }).collect();
            for run in 0..200 {
                assert_eq!(shards.iter().filter(|s| s.holds(run)).count(), 1);
            }
            for s in &shards {
                assert_eq!(s.size(200), (0..200).filter(|&r| s.holds(r)).count() as u64);
            }
        }
    }

    #[test]
    fn file_names_give_back_their_shard() {
        let shard = Shard {
            index: 5,
            count: 64,
        };
        assert_eq!(Shard::of_file_name(&shard.file_name()), Some((shard, true)));
        assert_eq!(
            Shard::of_file_name(&shard.partial_name()),
            Some((shard, false))
        );
        assert_eq!(Shard::of_file_name("shard-05-of-64.csv"), None);
        assert_eq!(Shard::of_file_name("runs.csv"), None);
    }

    #[test]
    fn long_lists_of_runs_are_cut() {
        assert_eq!(list_runs(&[3, 11]), "3, 11");
        let many: Vec<u64> = (0..25).collect();
        assert_eq!(list_runs(&many), "0, 1, 2, 3, 4, 5, 6, 7, 8, 9 and 15 more");
    }
}
