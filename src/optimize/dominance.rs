//! Pareto dominance for minimized objectives: the fast non-dominated sort and the crowding
//! distance of NSGA-II (Deb, Pratap, Agarwal & Meyarivan 2002, §III-A and §III-B).

/// Whether `a` dominates `b`: no objective worse and at least one better (all minimized).
pub fn dominates(a: &[f64], b: &[f64]) -> bool {
    let mut better = false;
    for (x, y) in a.iter().zip(b) {
        if x > y {
            return false;
        }
        better |= x < y;
    }
    better
}

/// The fronts of `points` (each a vector of minimized objectives), best first: front 0 is the
/// non-dominated set, front k the non-dominated set once fronts 0 … k−1 are removed. Indices
/// within a front ascend. O(M N²) (Deb et al. 2002, §III-A).
pub fn non_dominated_fronts(points: &[Vec<f64>]) -> Vec<Vec<usize>> {
    let n = points.len();
    let mut dominated_by = vec![0usize; n];
    let mut dominating: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        for j in i + 1..n {
            if dominates(&points[i], &points[j]) {
                dominating[i].push(j);
                dominated_by[j] += 1;
            } else if dominates(&points[j], &points[i]) {
                dominating[j].push(i);
                dominated_by[i] += 1;
            }
        }
    }
    let mut fronts = Vec::new();
    let mut current: Vec<usize> = (0..n).filter(|&i| dominated_by[i] == 0).collect();
    while !current.is_empty() {
        let mut next = Vec::new();
        for &i in &current {
            for &j in &dominating[i] {
                dominated_by[j] -= 1;
                if dominated_by[j] == 0 {
                    next.push(j);
                }
            }
        }
        next.sort_unstable();
        fronts.push(std::mem::replace(&mut current, next));
    }
    fronts
}

/// The indices of the non-dominated points of `points` (front 0), ascending.
pub fn pareto_indices(points: &[Vec<f64>]) -> Vec<usize> {
    non_dominated_fronts(points)
        .into_iter()
        .next()
        .unwrap_or_default()
}

/// The crowding distance of each point of one front (Deb et al. 2002, §III-B): per objective,
/// the points sorted by it, the extremes get +∞, each other point the gap between its two
/// neighbours divided by the objective's range; summed over the objectives. A point equal to
/// an earlier one in every objective gets 0, as in pymoo (a copy adds no spread), and a front
/// of at most two distinct points is all extremes.
pub fn crowding_distance(front: &[Vec<f64>]) -> Vec<f64> {
    let n = front.len();
    let mut distance = vec![0.0; n];
    let unique: Vec<usize> = (0..n)
        .filter(|&i| !front[..i].iter().any(|p| p == &front[i]))
        .collect();
    if unique.len() <= 2 {
        unique.iter().for_each(|&i| distance[i] = f64::INFINITY);
        return distance;
    }
    for m in 0..front[0].len() {
        add_gaps(front, &unique, m, &mut distance);
    }
    distance
}

/// Objective `m`'s share of the crowding distances of the `unique` points of `front`.
fn add_gaps(front: &[Vec<f64>], unique: &[usize], m: usize, distance: &mut [f64]) {
    let value = |i: usize| front[i][m];
    let mut order = unique.to_vec();
    order.sort_by(|&a, &b| value(a).total_cmp(&value(b)));
    let (first, last) = (order[0], order[order.len() - 1]);
    let range = value(last) - value(first);
    distance[first] = f64::INFINITY;
    distance[last] = f64::INFINITY;
    if range > 0.0 {
        for w in order.windows(3) {
            distance[w[1]] += (value(w[2]) - value(w[0])) / range;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[[f64; 2]]) -> Vec<Vec<f64>> {
        v.iter().map(|p| p.to_vec()).collect()
    }

    #[test]
    fn dominance_needs_one_strictly_better_objective() {
        assert!(dominates(&[1.0, 2.0], &[1.0, 3.0]));
        assert!(!dominates(&[1.0, 2.0], &[1.0, 2.0]));
        assert!(!dominates(&[0.0, 3.0], &[1.0, 2.0]));
    }

    /// Hand case: three layers, a duplicate, a point dominated by only one other.
    #[test]
    fn fronts_of_a_hand_case() {
        let p = pts(&[
            [1.0, 5.0], // 0: front 0
            [2.0, 3.0], // 1: front 0
            [4.0, 1.0], // 2: front 0
            [3.0, 4.0], // 3: dominated by 1 → front 1
            [2.0, 3.0], // 4: duplicate of 1 → front 0 (neither dominates)
            [5.0, 5.0], // 5: dominated by 3 → front 2
            [4.5, 2.0], // 6: dominated by 2 only → front 1
        ]);
        assert_eq!(
            non_dominated_fronts(&p),
            vec![vec![0, 1, 2, 4], vec![3, 6], vec![5]]
        );
        assert_eq!(pareto_indices(&p), vec![0, 1, 2, 4]);
    }

    #[test]
    fn fronts_of_no_points_and_of_a_chain() {
        assert!(non_dominated_fronts(&[]).is_empty());
        let chain = pts(&[[3.0, 3.0], [1.0, 1.0], [2.0, 2.0]]);
        assert_eq!(
            non_dominated_fronts(&chain),
            vec![vec![1], vec![2], vec![0]]
        );
    }

    #[test]
    fn crowding_distance_of_a_hand_front() {
        let f = pts(&[[0.0, 4.0], [1.0, 2.0], [3.0, 1.0], [4.0, 0.0], [1.0, 2.0]]);
        let d = crowding_distance(&f);
        assert_eq!(d[0], f64::INFINITY);
        assert_eq!(d[3], f64::INFINITY);
        // point 1: (3 − 0)/4 + (4 − 1)/4; point 2: (4 − 1)/4 + (2 − 0)/4; the copy: 0
        assert!((d[1] - 1.5).abs() < 1e-15, "{}", d[1]);
        assert!((d[2] - 1.25).abs() < 1e-15, "{}", d[2]);
        assert_eq!(d[4], 0.0);
        assert_eq!(
            crowding_distance(&pts(&[[1.0, 1.0], [1.0, 1.0], [2.0, 0.0]])),
            vec![f64::INFINITY, 0.0, f64::INFINITY]
        );
    }
}
