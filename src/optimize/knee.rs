//! The representative designs of a front: its extremes (the best design of each objective) and
//! a knee. The knee is the front point with the smallest sum of objectives normalized to
//! [0, 1] over the front; with two objectives the normalized extremes are (0, 1) and (1, 0),
//! so this is the point farthest below the line through the two extremes (the largest
//! distance to it, on the side of the ideal point), and with more objectives the point
//! farthest below the hyperplane through the unit points.

/// The index into `front` (minimized objectives) of each objective's best point, ties to the
/// first; empty for an empty front.
pub fn extremes(front: &[Vec<f64>]) -> Vec<usize> {
    let Some(first) = front.first() else {
        return Vec::new();
    };
    (0..first.len())
        .map(|m| {
            (0..front.len())
                .min_by(|&a, &b| front[a][m].total_cmp(&front[b][m]).then(a.cmp(&b)))
                .unwrap_or(0)
        })
        .collect()
}

/// The index into `front` of its knee; `None` for an empty front.
pub fn knee(front: &[Vec<f64>]) -> Option<usize> {
    let k = front.first()?.len();
    let range: Vec<(f64, f64)> = (0..k)
        .map(|m| {
            front
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[m]), hi.max(p[m]))
                })
        })
        .collect();
    let normalized_sum = |p: &Vec<f64>| -> f64 {
        p.iter()
            .zip(&range)
            .map(|(x, (lo, hi))| if hi > lo { (x - lo) / (hi - lo) } else { 0.0 })
            .sum()
    };
    (0..front.len()).min_by(|&a, &b| {
        normalized_sum(&front[a])
            .total_cmp(&normalized_sum(&front[b]))
            .then(a.cmp(&b))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_knee_of_a_bent_front_is_its_bend() {
        let front = vec![
            vec![0.0, 10.0],
            vec![1.0, 3.0],
            vec![2.0, 1.0],
            vec![6.0, 0.5],
            vec![10.0, 0.0],
        ];
        assert_eq!(extremes(&front), vec![0, 4]);
        // normalized sums: 1, 0.4, 0.3, 0.65, 1
        assert_eq!(knee(&front), Some(2));
        assert_eq!(knee(&[]), None);
        assert_eq!(knee(&[vec![1.0, 1.0]]), Some(0));
    }
}
