//! Mutations of corpus files, as proptest strategies (so a failing case shrinks to few, small
//! edits): byte flips, deletions, token insertions, splices from other files, repeats and
//! numeric blow-ups. Every mutation adds a bounded number of bytes, so inputs stay small.

use crate::corpus::Entry;
use proptest::prelude::*;
use proptest::sample::Index;

/// Most mutations applied to one corpus file.
pub const MAX_MUTATIONS: usize = 4;
/// Longest run copied by a splice or a repeat.
const MAX_COPY: usize = 32;
/// Most copies a repeat makes.
const MAX_REPEAT: usize = 8;

/// One edit of an input.
#[derive(Clone, Debug)]
pub enum Mutation {
    FlipBit {
        at: Index,
        bit: u8,
    },
    SetByte {
        at: Index,
        byte: u8,
    },
    Delete {
        at: Index,
        len: usize,
    },
    Insert {
        at: Index,
        token: &'static str,
    },
    /// Copies up to `len` bytes of another corpus file to `at`.
    Splice {
        at: Index,
        donor: Index,
        from: Index,
        len: usize,
    },
    /// Repeats the `len` bytes at `at`, `times` more times.
    Repeat {
        at: Index,
        len: usize,
        times: usize,
    },
    /// Replaces one of the input's numbers with `value`.
    BlowUp {
        which: Index,
        value: &'static str,
    },
    Truncate {
        at: Index,
    },
}

/// A case: which corpus file and what to do to it.
#[derive(Clone, Debug)]
pub struct Case {
    pub file: Index,
    pub mutations: Vec<Mutation>,
}

/// The strategy of cases for a target with this vocabulary and these numeric extremes.
pub fn cases(
    vocabulary: &'static [&'static str],
    blow_ups: &'static [&'static str],
) -> BoxedStrategy<Case> {
    let mutation = mutation(vocabulary, blow_ups);
    (
        any::<Index>(),
        prop::collection::vec(mutation, 1..=MAX_MUTATIONS),
    )
        .prop_map(|(file, mutations)| Case { file, mutations })
        .boxed()
}

fn mutation(
    vocabulary: &'static [&'static str],
    blow_ups: &'static [&'static str],
) -> BoxedStrategy<Mutation> {
    prop_oneof![
        (any::<Index>(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        (any::<Index>(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        (any::<Index>(), 1..=MAX_COPY).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<Index>(), prop::sample::select(vocabulary))
            .prop_map(|(at, token)| Mutation::Insert { at, token }),
        (any::<Index>(), any::<Index>(), any::<Index>(), 1..=MAX_COPY).prop_map(
            |(at, donor, from, len)| Mutation::Splice {
                at,
                donor,
                from,
                len
            }
        ),
        (any::<Index>(), 1..=MAX_COPY, 1..=MAX_REPEAT)
            .prop_map(|(at, len, times)| Mutation::Repeat { at, len, times }),
        (any::<Index>(), prop::sample::select(blow_ups))
            .prop_map(|(which, value)| Mutation::BlowUp { which, value }),
        any::<Index>().prop_map(|at| Mutation::Truncate { at }),
    ]
    .boxed()
}

/// The bytes of `case`, made from `corpus` (which must not be empty).
pub fn apply(case: &Case, corpus: &[Entry]) -> Vec<u8> {
    let Some(seed) = corpus.get(case.file.index(corpus.len().max(1))) else {
        return Vec::new();
    };
    let mut bytes = seed.bytes.clone();
    for m in &case.mutations {
        apply_one(m, &mut bytes, corpus);
    }
    bytes
}

fn apply_one(m: &Mutation, bytes: &mut Vec<u8>, corpus: &[Entry]) {
    // An insertion point may be the end; an existing byte needs a non-empty input.
    let point = |at: &Index, len: usize| at.index(len + 1);
    match m {
        Mutation::FlipBit { at, bit } => {
            if !bytes.is_empty() {
                let i = at.index(bytes.len());
                bytes[i] ^= 1 << bit;
            }
        }
        Mutation::SetByte { at, byte } => {
            if !bytes.is_empty() {
                let i = at.index(bytes.len());
                bytes[i] = *byte;
            }
        }
        Mutation::Delete { at, len } => {
            let start = point(at, bytes.len());
            let end = (start + len).min(bytes.len());
            bytes.drain(start..end);
        }
        Mutation::Insert { at, token } => {
            let i = point(at, bytes.len());
            bytes.splice(i..i, token.bytes());
        }
        Mutation::Splice {
            at,
            donor,
            from,
            len,
        } => {
            let piece = slice_of(corpus, donor, from, *len);
            let i = point(at, bytes.len());
            bytes.splice(i..i, piece);
        }
        Mutation::Repeat { at, len, times } => repeat(bytes, at, *len, *times),
        Mutation::BlowUp { which, value } => blow_up(bytes, which, value),
        Mutation::Truncate { at } => {
            let i = point(at, bytes.len());
            bytes.truncate(i);
        }
    }
}

fn slice_of(corpus: &[Entry], donor: &Index, from: &Index, len: usize) -> Vec<u8> {
    let Some(entry) = corpus.get(donor.index(corpus.len().max(1))) else {
        return Vec::new();
    };
    if entry.bytes.is_empty() {
        return Vec::new();
    }
    let start = from.index(entry.bytes.len());
    let end = (start + len).min(entry.bytes.len());
    entry.bytes[start..end].to_vec()
}

fn repeat(bytes: &mut Vec<u8>, at: &Index, len: usize, times: usize) {
    if bytes.is_empty() {
        return;
    }
    let start = at.index(bytes.len());
    let end = (start + len).min(bytes.len());
    let piece = bytes[start..end].to_vec();
    let copies: Vec<u8> = piece
        .iter()
        .copied()
        .cycle()
        .take(piece.len() * times)
        .collect();
    bytes.splice(end..end, copies);
}

/// Replaces the `which`-th number (a run of digits and dots not inside a name, with its
/// minus sign) by `value`; an input without numbers gets `value` appended.
fn blow_up(bytes: &mut Vec<u8>, which: &Index, value: &str) {
    let numbers = numbers(bytes);
    if numbers.is_empty() {
        bytes.extend_from_slice(value.as_bytes());
        return;
    }
    let (start, end) = numbers[which.index(numbers.len())];
    bytes.splice(start..end, value.bytes());
}

/// Byte ranges of the numbers in `bytes`.
pub fn numbers(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let in_name = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if !bytes[i].is_ascii_digit() || in_name {
            i += 1;
            continue;
        }
        let start = if i > 0 && bytes[i - 1] == b'-' {
            i - 1
        } else {
            i
        };
        let mut end = i;
        while end < bytes.len() && (bytes[end].is_ascii_digit() || bytes[end] == b'.') {
            end += 1;
        }
        out.push((start, end));
        i = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_skip_names_and_keep_signs() {
        let text = b"M0 = -12.5, x3 7";
        let found: Vec<&[u8]> = numbers(text)
            .into_iter()
            .map(|(s, e)| &text[s..e])
            .collect();
        assert_eq!(found, vec![&b"-12.5"[..], &b"7"[..]]);
    }

    #[test]
    fn a_blow_up_replaces_one_number() {
        let mut bytes = b"seeds = 2\nfirst_seed = 1\n".to_vec();
        let mut runner = proptest::test_runner::TestRunner::deterministic();
        let which = any::<Index>()
            .new_tree(&mut runner)
            .map(|tree| proptest::strategy::ValueTree::current(&tree))
            .expect("an index is always generated");
        blow_up(&mut bytes, &which, "4294967296");
        let text = String::from_utf8_lossy(&bytes);
        assert_eq!(text.matches("4294967296").count(), 1, "{text}");
        assert_eq!(numbers(&bytes).len(), 2);
    }
}
