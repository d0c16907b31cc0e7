//! "Did you mean": the known name closest to a mistyped one.

/// The candidate closest to `word` when it is close enough to be a typo (a Jaro–Winkler
/// similarity of at least 0.8, or `word` differing by one or two edits).
pub fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    candidates
        .into_iter()
        .filter(|c| *c != word)
        .map(|c| (strsim::jaro_winkler(word, c), c))
        .filter(|(score, c)| {
            *score >= 0.8 || strsim::damerau_levenshtein(word, c) <= 2.min(c.len() / 2)
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

/// `; did you mean `X`?` for `word` among `candidates`, or nothing.
pub fn hint<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    did_you_mean(word, candidates)
        .map(|c| format!("; did you mean `{c}`?"))
        .unwrap_or_default()
}

/// A serde message about an unknown field or variant (`unknown field `wrold`, expected one of
/// `name`, `world``) with the closest expected name added.
pub fn explain(message: &str) -> String {
    let Some(rest) = message
        .strip_prefix("unknown field `")
        .or_else(|| message.strip_prefix("unknown variant `"))
    else {
        return message.to_string();
    };
    let Some((word, expected)) = rest.split_once('`') else {
        return message.to_string();
    };
    let names: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    format!("{message}{}", hint(word, names))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_find_their_name() {
        assert_eq!(
            did_you_mean("wrold", ["name", "world", "start"]),
            Some("world")
        );
        assert_eq!(
            did_you_mean("tolerence", ["agents", "tolerance"]),
            Some("tolerance")
        );
        assert_eq!(did_you_mean("zzz", ["world", "start"]), None);
        assert_eq!(
            explain("unknown field `wrold`, expected one of `name`, `world`, `start`"),
            "unknown field `wrold`, expected one of `name`, `world`, `start`; did you mean `world`?"
        );
        assert_eq!(
            explain("unknown field `k2`, expected `k` or `iterations`"),
            "unknown field `k2`, expected `k` or `iterations`; did you mean `k`?"
        );
        assert_eq!(explain("missing field `a`"), "missing field `a`");
    }
}
