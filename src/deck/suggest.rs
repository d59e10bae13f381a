//! "Did you mean …?": the known name closest to a misspelled one.
//!
//! Closeness is the optimal-string-alignment distance (Levenshtein with a swap of two adjacent
//! characters counted as one edit), so that `CQAUD4` is one edit from `CQUAD4`. A name at most
//! [`max_edits`] edits away is suggested; ties go to the first name of the list.

/// The most edits a suggestion may be away from a name of `length` characters: one for names
/// of up to four characters (two edits turn `PROD` into `GRID`, a different card, not a typo of
/// it), two for longer ones.
pub fn max_edits(length: usize) -> usize {
    if length <= 4 { 1 } else { 2 }
}

/// The name of `known` closest to `word` (ASCII case ignored), if it is at most
/// [`max_edits`] edits away and not `word` itself.
pub fn closest<'a>(word: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let word = word.to_ascii_uppercase();
    let limit = max_edits(word.chars().count());
    known
        .into_iter()
        .map(|k| (edit_distance(&word, &k.to_ascii_uppercase()), k))
        .filter(|(d, _)| (1..=limit).contains(d))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Optimal-string-alignment distance between `a` and `b` (insertions, deletions,
/// substitutions and adjacent transpositions, each one edit).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    // d[i][j]: distance between the first i characters of a and the first j of b.
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transposition_is_one_edit() {
        assert_eq!(edit_distance("CQAUD4", "CQUAD4"), 1);
        assert_eq!(edit_distance("CQUAD", "CQUAD4"), 1);
        assert_eq!(edit_distance("CBAR", "CQUAD4"), 4);
        assert_eq!(edit_distance("", "ABC"), 3);
    }

    #[test]
    fn suggests_only_close_names() {
        let known = ["CQUAD4", "CTRIA3", "GRID"];
        assert_eq!(closest("cqaud4", known), Some("CQUAD4"));
        assert_eq!(closest("GIRD", known), Some("GRID"));
        assert_eq!(closest("CBAR", known), None);
        assert_eq!(
            closest("PROD", known),
            None,
            "two edits from GRID: another card, not a typo"
        );
        assert_eq!(closest("GRD", known), Some("GRID"));
        assert_eq!(closest("GRID", known), None);
    }
}
