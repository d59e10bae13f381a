//! The full-factorial design of a space, for validation studies: `levels` evenly spaced values
//! (bounds included) of each continuous variable, every allowed value of each discrete one, all
//! combinations with the last variable varying fastest.

use super::space::{Design, DesignSpace, Domain};

/// The values one variable takes in the grid.
fn levels_of(domain: &Domain, levels: usize) -> Vec<f64> {
    match domain {
        Domain::Discrete { values } => values.clone(),
        Domain::Continuous { low, high } if levels <= 1 || low == high => vec![0.5 * (low + high)],
        Domain::Continuous { low, high } => (0..levels)
            .map(|i| low + (high - low) * i as f64 / (levels - 1) as f64)
            .collect(),
    }
}

/// The number of designs of the full-factorial grid.
pub fn grid_size(space: &DesignSpace, levels: usize) -> usize {
    space
        .variables
        .iter()
        .map(|v| levels_of(&v.domain, levels).len())
        .product()
}

/// Every design of the full-factorial grid.
pub fn full_factorial(space: &DesignSpace, levels: usize) -> Vec<Design> {
    let axes: Vec<Vec<f64>> = space
        .variables
        .iter()
        .map(|v| levels_of(&v.domain, levels))
        .collect();
    let mut designs: Vec<Design> = vec![Vec::new()];
    for axis in &axes {
        designs = designs
            .iter()
            .flat_map(|d| {
                axis.iter().map(move |x| {
                    let mut next = d.clone();
                    next.push(*x);
                    next
                })
            })
            .collect();
    }
    designs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::space::Variable;

    #[test]
    fn three_levels_by_a_discrete_pair() {
        let space = DesignSpace::new(vec![
            Variable::continuous("x", 0.0, 1.0),
            Variable::discrete("n", &[8.0, 6.0]),
        ]);
        assert_eq!(grid_size(&space, 3), 6);
        assert_eq!(
            full_factorial(&space, 3),
            vec![
                vec![0.0, 6.0],
                vec![0.0, 8.0],
                vec![0.5, 6.0],
                vec![0.5, 8.0],
                vec![1.0, 6.0],
                vec![1.0, 8.0]
            ]
        );
    }
}
