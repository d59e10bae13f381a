//! The hypervolume indicator: the measure of the region dominated by a set of points (all
//! objectives minimized) and bounded by a reference point (Zitzler & Thiele 1998). Points that
//! do not strictly dominate the reference point add nothing.
//!
//! Two objectives: an exact sweep in O(n log n) (points sorted by the first objective, each
//! adding the rectangle between its second objective and the best one so far). More: the exact
//! "hypervolume by slicing objectives" recursion (While, Hingston, Barone & Huband 2006), which
//! slices along the last objective and sums slab thickness × the (k−1)-D hypervolume of the
//! points below the slab; exponential in k, meant for the few objectives and front sizes of a
//! design study.

/// The hypervolume of `points` (each of the reference point's length) up to `reference`.
pub fn hypervolume(points: &[Vec<f64>], reference: &[f64]) -> f64 {
    let inside: Vec<&[f64]> = points
        .iter()
        .map(Vec::as_slice)
        .filter(|p| p.iter().zip(reference).all(|(x, r)| x < r))
        .collect();
    slices(inside, reference)
}

/// The hypervolume of points that all strictly dominate `reference`.
fn slices(mut points: Vec<&[f64]>, reference: &[f64]) -> f64 {
    let k = reference.len();
    match k {
        0 => 0.0,
        1 => points
            .iter()
            .map(|p| reference[0] - p[0])
            .fold(0.0, f64::max),
        2 => sweep_2d(points, reference),
        _ => {
            points.sort_by(|a, b| a[k - 1].total_cmp(&b[k - 1]));
            let mut volume = 0.0;
            for i in 0..points.len() {
                let top = points.get(i + 1).map_or(reference[k - 1], |p| p[k - 1]);
                let thickness = top - points[i][k - 1];
                if thickness > 0.0 {
                    let below: Vec<&[f64]> = points[..=i].iter().map(|p| &p[..k - 1]).collect();
                    volume += thickness * slices(below, &reference[..k - 1]);
                }
            }
            volume
        }
    }
}

/// The exact 2-D hypervolume by a sweep over the first objective.
fn sweep_2d(mut points: Vec<&[f64]>, reference: &[f64]) -> f64 {
    points.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut best = reference[1];
    let mut area = 0.0;
    for p in points {
        if p[1] < best {
            area += (reference[0] - p[0]) * (best - p[1]);
            best = p[1];
        }
    }
    area
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn staircase_of_three_points() {
        // union of [1,4]×[3,4], [2,4]×[2,4], [3,4]×[1,4]: 3·1 + 2·1 + 1·1 = 6
        let p = vec![
            vec![1.0, 3.0],
            vec![2.0, 2.0],
            vec![3.0, 1.0],
            vec![2.5, 2.5],
        ];
        assert_eq!(hypervolume(&p, &[4.0, 4.0]), 6.0);
        // a point on the reference's boundary adds nothing
        let q = vec![vec![4.0, 0.0], vec![1.0, 3.0]];
        assert_eq!(hypervolume(&q, &[4.0, 4.0]), 3.0);
        assert_eq!(hypervolume(&[], &[4.0, 4.0]), 0.0);
    }

    /// Three objectives: three boxes whose union is checked by inclusion–exclusion.
    #[test]
    fn three_objectives_by_inclusion_exclusion() {
        let r = [3.0, 3.0, 3.0];
        let a = vec![1.0, 1.0, 1.0]; // box 2×2×2 = 8
        let b = vec![0.0, 2.0, 2.0]; // box 3×1×1 = 3, overlap with a: 2×1×1 = 2
        let c = vec![2.0, 0.0, 0.0]; // box 1×3×3 = 9, overlap a: 1×2×2 = 4, b: 1×1×1 = 1, abc: 1×1×1 = 1
        let hv = hypervolume(&[a, b, c], &r);
        assert_eq!(hv, 8.0 + 3.0 + 9.0 - 2.0 - 4.0 - 1.0 + 1.0);
    }

    /// The k-D recursion equals the 2-D sweep when the third objective is constant.
    #[test]
    fn slicing_reduces_to_the_sweep() {
        let p2 = vec![
            vec![0.1, 0.9],
            vec![0.4, 0.3],
            vec![0.8, 0.2],
            vec![0.5, 0.5],
        ];
        let p3: Vec<Vec<f64>> = p2.iter().map(|p| vec![p[0], p[1], 0.0]).collect();
        let hv2 = hypervolume(&p2, &[1.0, 1.0]);
        let hv3 = hypervolume(&p3, &[1.0, 1.0, 2.0]);
        assert!((hv3 - 2.0 * hv2).abs() < 1e-15, "{hv3} vs 2 × {hv2}");
    }
}
