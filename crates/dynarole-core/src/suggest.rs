//! "Did you mean ...?" suggestions for misspelt names.

/// The candidate closest to `name`, if it is close enough to be a likely typo.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let mut best: Option<(f64, &str)> = None;
    for candidate in candidates {
        let score = strsim::jaro_winkler(&name.to_lowercase(), &candidate.to_lowercase());
        if score >= 0.8 && best.is_none_or(|(s, _)| score > s) {
            best = Some((score, candidate));
        }
    }
    best.map(|(_, c)| c.to_string())
}

/// "did you mean `y`?" when `name` is a likely typo of one of `candidates`: the one wording of
/// the suggestion for every unknown name (robots, sequences, TOML keys).
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    closest(name, candidates).map(|close| format!("did you mean `{close}`?"))
}

/// `MO` or `Ml2` read as `M0` and `M12`: letters that look like digits (OCR and typing slips).
pub fn module_label_lookalike(name: &str) -> Option<String> {
    let rest = name.strip_prefix('M')?;
    if rest.is_empty() || rest.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let digits: String = rest
        .chars()
        .map(|c| match c {
            'O' | 'o' => Some('0'),
            'I' | 'l' => Some('1'),
            c if c.is_ascii_digit() => Some(c),
            _ => None,
        })
        .collect::<Option<String>>()?;
    Some(format!("M{digits}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookalikes() {
        assert_eq!(module_label_lookalike("MO"), Some("M0".into()));
        assert_eq!(module_label_lookalike("Ml2"), Some("M12".into()));
        assert_eq!(module_label_lookalike("M3"), None);
        assert_eq!(module_label_lookalike("Mx"), None);
    }

    #[test]
    fn closest_name() {
        assert_eq!(
            closest("retrakt", ["extend", "retract"]),
            Some("retract".into())
        );
        assert_eq!(closest("zzz", ["extend", "retract"]), None);
    }
}
