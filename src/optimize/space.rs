//! The design space: continuous variables between bounds and discrete variables on a set of
//! allowed values (Nastran `DESVAR` without and with `DDVAL`).
//!
//! The search works on a genome with one coordinate per variable: the value itself for a
//! continuous variable, the index into the sorted value set for a discrete one. A discrete
//! variable is thus an integer variable on `0 … n−1`, handled as pymoo's mixed-variable route
//! handles its `Integer` variables (SBX and polynomial mutation on the real line, then a
//! rounding repair): the rounding is onto the index, so an unevenly spaced set (6, 8, 10, 16
//! plies) is searched with each allowed value one step from its neighbours.

/// One design: the value of every variable, in the order of the [`DesignSpace`].
pub type Design = Vec<f64>;

/// The domain of one design variable.
#[derive(Debug, Clone, PartialEq)]
pub enum Domain {
    /// Any value in `[low, high]`.
    Continuous { low: f64, high: f64 },
    /// One of `values` (sorted ascending, without repeats).
    Discrete { values: Vec<f64> },
}

/// A named design variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    pub name: String,
    pub domain: Domain,
}

impl Variable {
    /// A continuous variable on `[low, high]`.
    pub fn continuous(name: impl Into<String>, low: f64, high: f64) -> Self {
        Variable {
            name: name.into(),
            domain: Domain::Continuous { low, high },
        }
    }

    /// Whether `x` is a value of the variable: within its bounds, or one of its values.
    pub fn contains(&self, x: f64) -> bool {
        match &self.domain {
            Domain::Continuous { low, high } => (*low..=*high).contains(&x),
            Domain::Discrete { values } => values.contains(&x),
        }
    }

    /// A discrete variable on `values` (sorted, repeats dropped).
    pub fn discrete(name: impl Into<String>, values: &[f64]) -> Self {
        let mut values = values.to_vec();
        values.sort_by(f64::total_cmp);
        values.dedup();
        Variable {
            name: name.into(),
            domain: Domain::Discrete { values },
        }
    }

    /// The genome coordinate's bounds: the value's, or `[0, n − 1]` for a discrete variable.
    pub fn gene_bounds(&self) -> (f64, f64) {
        match &self.domain {
            Domain::Continuous { low, high } => (*low, *high),
            Domain::Discrete { values } => (0.0, values.len().saturating_sub(1) as f64),
        }
    }

    /// Whether the genome coordinate is an integer (a discrete variable's index).
    pub fn is_discrete(&self) -> bool {
        matches!(self.domain, Domain::Discrete { .. })
    }

    /// The variable's value for genome coordinate `gene`: the gene itself, or the allowed value
    /// at the gene rounded to the nearest index.
    pub fn value(&self, gene: f64) -> f64 {
        match &self.domain {
            Domain::Continuous { .. } => gene,
            Domain::Discrete { values } => values[round_index(gene, values.len())],
        }
    }
}

/// `gene` rounded to the nearest index in `0 … n − 1` (halves away from zero, as numpy's
/// `round` is not: ties are measure-zero for real genes, so the choice does not matter).
fn round_index(gene: f64, n: usize) -> usize {
    (gene.round().max(0.0) as usize).min(n - 1)
}

/// The design variables of a study, in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DesignSpace {
    pub variables: Vec<Variable>,
}

impl DesignSpace {
    pub fn new(variables: Vec<Variable>) -> Self {
        DesignSpace { variables }
    }

    pub fn len(&self) -> usize {
        self.variables.len()
    }

    pub fn is_empty(&self) -> bool {
        self.variables.is_empty()
    }

    /// The design a genome encodes.
    pub fn design(&self, genome: &[f64]) -> Design {
        self.variables
            .iter()
            .zip(genome)
            .map(|(v, g)| v.value(*g))
            .collect()
    }

    /// `genome` with every discrete coordinate rounded onto its index set (pymoo's
    /// `RoundingRepair` of the mixed-variable route).
    pub fn repair(&self, genome: &mut [f64]) {
        for (v, g) in self.variables.iter().zip(genome.iter_mut()) {
            if let Domain::Discrete { values } = &v.domain {
                *g = round_index(*g, values.len()) as f64;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_discrete_gene_rounds_onto_the_index_of_the_value_set() {
        let plies = Variable::discrete("n", &[12.0, 6.0, 8.0, 10.0, 8.0]);
        assert_eq!(plies.gene_bounds(), (0.0, 3.0));
        assert_eq!(plies.value(0.49), 6.0);
        assert_eq!(plies.value(0.51), 8.0);
        assert_eq!(plies.value(2.7), 12.0);
        assert_eq!(plies.value(-0.2), 6.0);
        let space = DesignSpace::new(vec![Variable::continuous("t", 0.0, 90.0), plies]);
        let mut genome = vec![33.3, 1.6];
        space.repair(&mut genome);
        assert_eq!(genome, vec![33.3, 2.0]);
        assert_eq!(space.design(&genome), vec![33.3, 10.0]);
    }
}
