//! What a campaign's rows are computed from: dynarole's version with a hash of the source it
//! was built from (`build.rs`: two builds of one version from different code differ), and a
//! hash of every file a run reads (the campaign file, the program, its robot plugins, the start and expected
//! configurations). The record is kept beside `runs.csv` and in a split's directory
//! (`campaign.inputs`) and heads every shard file, so that rows computed from different
//! inputs (an edited `.dr` file, a shard run elsewhere with another `expect`) are never
//! merged or resumed together. Every option that changes a result is in the campaign file;
//! the command line's (`-j`, `--max-runs`, the split) change only which runs are done where.

use std::path::Path;

/// The record beside `runs.csv`, and in a directory of shards.
pub const INPUTS_FILE: &str = "campaign.inputs";

/// The first line of a record.
const MARKER: &str = "# dynarole campaign inputs: what the runs were computed from";

/// One input: its role, its hash (for `version`, dynarole's version) and its path as read.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Input {
    role: String,
    hash: String,
    path: String,
}

/// The inputs of a campaign, in the order they are read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    inputs: Vec<Input>,
}

/// The roles, in order, and how a change of each is said.
const ROLES: [(&str, &str); 6] = [
    (
        "version",
        "another build of dynarole (its version or its source)",
    ),
    ("campaign", "another campaign file"),
    ("program", "another program"),
    ("plugin", "another robot plugin"),
    ("from", "another start configuration (from)"),
    ("expect", "another expected configuration (expect)"),
];

impl Default for Fingerprint {
    fn default() -> Fingerprint {
        Fingerprint::new()
    }
}

impl Fingerprint {
    /// A record of this build of dynarole and no file yet.
    pub fn new() -> Fingerprint {
        let version = Input {
            role: "version".into(),
            hash: build_identity().into(),
            path: String::new(),
        };
        Fingerprint {
            inputs: vec![version],
        }
    }

    /// Adds the file at `path` with the text it was read as, in `role`.
    pub fn add(&mut self, role: &str, path: &Path, text: &str) {
        self.inputs.push(Input {
            role: role.into(),
            hash: hash_text(text),
            path: path.display().to_string().escape_debug().to_string(),
        });
    }

    /// The hash this record gives the campaign file.
    pub fn campaign_hash(&self) -> Option<&str> {
        self.inputs
            .iter()
            .find(|i| i.role == "campaign")
            .map(|i| i.hash.as_str())
    }

    /// The record as `#` lines (the head of a shard file, or all of `campaign.inputs`).
    pub fn to_text(&self) -> String {
        let mut text = format!("{MARKER}\n");
        for i in &self.inputs {
            let line = format!("# {} {} {}", i.role, i.hash, i.path);
            text.push_str(line.trim_end());
            text.push('\n');
        }
        text
    }

    /// The record in the `#` lines at the head of `text`, if they are one; the number of
    /// those lines, with it.
    pub fn parse(text: &str) -> (Option<Fingerprint>, usize) {
        let head: Vec<&str> = text
            .split_inclusive('\n')
            .take_while(|l| l.starts_with('#') && l.ends_with('\n'))
            .collect();
        let mut lines = head.iter().map(|l| l.trim_end_matches(['\n', '\r']));
        if lines.next() != Some(MARKER) {
            return (None, head.len());
        }
        let inputs: Option<Vec<Input>> = lines.map(input_of_line).collect();
        (inputs.map(|inputs| Fingerprint { inputs }), head.len())
    }

    /// What differs from `self` in `now`, in words (`another program: FILE changed`); empty
    /// when the runs of both are the same. Paths do not count: a moved file is the same input.
    pub fn changes(&self, now: &Fingerprint) -> Vec<String> {
        ROLES
            .iter()
            .filter_map(|&(role, words)| {
                let of = |f: &Fingerprint| -> Vec<Input> {
                    f.inputs
                        .iter()
                        .filter(|i| i.role == role)
                        .cloned()
                        .collect()
                };
                let (before, after) = (of(self), of(now));
                let hashes = |v: &[Input]| v.iter().map(|i| i.hash.clone()).collect::<Vec<_>>();
                (hashes(&before) != hashes(&after)).then(|| describe(role, words, &before, &after))
            })
            .collect()
    }
}

/// `# ROLE HASH PATH`.
fn input_of_line(line: &str) -> Option<Input> {
    let mut parts = line.strip_prefix("# ")?.splitn(3, ' ');
    Some(Input {
        role: parts.next()?.into(),
        hash: parts.next()?.into(),
        path: parts.next().unwrap_or("").into(),
    })
}

/// `another program: eight2car.dr changed`, or, when the inputs were read from
/// other paths, `another program: B.dr instead of A.dr`.
fn describe(role: &str, words: &str, before: &[Input], after: &[Input]) -> String {
    if role == "version" {
        let v = |x: &[Input]| x.first().map_or("?".to_string(), |i| i.hash.clone());
        return format!("{words} ({}, now {})", v(before), v(after));
    }
    let only = |these: &[Input], those: &[Input]| -> String {
        let mut paths: Vec<&str> = Vec::new();
        for i in these
            .iter()
            .filter(|i| !those.iter().any(|o| o.hash == i.hash))
        {
            if !paths.contains(&i.path.as_str()) {
                paths.push(&i.path);
            }
        }
        if paths.is_empty() {
            "none".into()
        } else {
            paths.join(", ")
        }
    };
    let (was, now) = (only(before, after), only(after, before));
    if was == now {
        format!("{words}: {now} changed")
    } else {
        format!("{words}: {now} instead of {was}")
    }
}

/// This build: dynarole's version and the hash of the source it was built from
/// (`0.1.0+5c1e...`).
pub fn build_identity() -> &'static str {
    concat!(env!("CARGO_PKG_VERSION"), "+", env!("DYNAROLE_SOURCE"))
}

/// A 64-bit FNV-1a hash of `text`, in hex (stable across machines and versions of Rust, unlike
/// the standard library's hasher; a check of what was read, not a defence against forgery).
pub fn hash_text(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{hash:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(program: &str) -> Fingerprint {
        let mut f = Fingerprint::new();
        f.add("campaign", Path::new("c.toml"), "seeds = 1");
        f.add("program", Path::new("a b.dr"), program);
        f
    }

    #[test]
    fn records_read_back_and_name_what_changed() {
        let before = record("robot snakebot;");
        let text = before.to_text();
        assert_eq!(Fingerprint::parse(&text), (Some(before.clone()), 4));
        assert!(before.changes(&record("robot snakebot;")).is_empty());
        assert_eq!(
            before.changes(&record("robot snakebot; // edited")),
            vec!["another program: a b.dr changed".to_string()]
        );
        assert_eq!(Fingerprint::parse("run,axis\n"), (None, 0));
    }

    /// Rows of another build are told apart even at the same version: the source's hash is in
    /// the record, and a change of it is named.
    #[test]
    fn another_build_of_one_version_is_another_input() {
        let (version, source) = build_identity().split_once('+').expect("version+source");
        assert_eq!(version, env!("CARGO_PKG_VERSION"));
        assert!(
            source.len() == 16 && source.chars().all(|c| c.is_ascii_hexdigit()),
            "{source}"
        );
        let now = record("robot snakebot;");
        let text = now.to_text().replace(source, "0123456789abcdef");
        let (before, _) = Fingerprint::parse(&text);
        let changes = before.expect("a record").changes(&now);
        assert_eq!(changes.len(), 1, "{changes:?}");
        assert!(
            changes[0].starts_with("another build of dynarole"),
            "{changes:?}"
        );
        assert!(changes[0].contains("0123456789abcdef"), "{changes:?}");
    }
}
