//! A pROM in time (thesis eq. 3.31): M_r(p) q̈ + C_r(p) q̇ + K_r(p) q = S_r u(t) as an integrator
//! [`Backend`] whose parameters may follow tables of time ([`VaryingProm`]), and the reduced
//! states that produce given displacements at the pROM's inputs ([`InputStaticShapes`]).

use faer::Mat;
use faer::MatRef;
use faer::linalg::solvers::Solve;

use crate::dynamics::integrators::{
    Backend, Combination, DenseOperators, IntegrationError, LinearSystem,
};
use crate::dynamics::table::Table;
use crate::rom::prom::{Prom, PromEvaluation};

/// The pROM as an integrator backend. Parameters following tables (PTABLE) are re-evaluated
/// before each step; when p(t) changed, M_r, C_r, K_r are summed again ([`Prom::evaluate`],
/// allocation-free, O(n_terms · n_r²)) and the effective matrix is formed and inverted again
/// (O(n_r³); ≈ 30 µs at n_r = 31), so a table that changes every step costs that per step and
/// a constant table costs nothing. The matrices are those at the end of the step (t_{k+1}).
/// The reduced mass's conditioning is the caller's to check once, at the starting point, not at
/// every re-evaluation (an eigenvalue decomposition per step would dominate the cost).
pub struct VaryingProm<'a> {
    prom: &'a Prom,
    /// The pROM at the current parameter values.
    pub at: PromEvaluation,
    /// The current parameter values.
    pub p: Vec<f64>,
    /// (parameter index, p(t)).
    tables: Vec<(usize, Table)>,
    ops: DenseOperators,
    /// Parameters found outside the pROM's box at any time.
    pub outside: Vec<String>,
    /// Evaluations of the pROM so far (1 + the changes of tabulated parameters).
    pub evaluations: usize,
}

impl<'a> VaryingProm<'a> {
    /// The pROM starting from its evaluation `at` at `p`, with the parameters of `tables`
    /// (parameter index, p(t)) following them; `outside` lists the parameters already outside
    /// the box. Evaluated at the first [`Backend::advance`].
    pub fn new(
        prom: &'a Prom,
        at: PromEvaluation,
        p: Vec<f64>,
        tables: Vec<(usize, Table)>,
        outside: Vec<String>,
    ) -> Self {
        VaryingProm {
            prom,
            at,
            p,
            tables,
            ops: DenseOperators::default(),
            outside,
            evaluations: 0,
        }
    }
}

impl Backend for VaryingProm<'_> {
    fn size(&self) -> usize {
        self.prom.size()
    }
    fn prepare(
        &mut self,
        effective: Combination,
        products: &[Combination],
        what: &'static str,
    ) -> Result<(), IntegrationError> {
        let sys = LinearSystem {
            mass: self.at.mass(),
            damping: self.at.damping(),
            stiffness: self.at.stiffness(),
        };
        self.ops.prepare(sys, effective, products, what)
    }
    fn apply(&self, j: usize, x: &[f64], y: &mut [f64]) {
        self.ops.apply(j, x, y);
    }
    fn solve(&mut self, x: &mut [f64]) -> Result<(), IntegrationError> {
        self.ops.solve(x);
        Ok(())
    }
    fn advance(&mut self, t: f64) -> Result<bool, IntegrationError> {
        let mut changed = self.evaluations == 0;
        for (j, table) in &self.tables {
            let value = table.value(t);
            if value != self.p[*j] {
                self.p[*j] = value;
                changed = true;
            }
        }
        if changed {
            self.prom
                .evaluate(&self.p, &mut self.at)
                .map_err(|e| IntegrationError::Backend(format!("t = {t}: {e}")))?;
            self.evaluations += 1;
            for name in self.prom.outside_box(&self.p) {
                if !self.outside.iter().any(|x| x == name) {
                    self.outside.push(name.to_string());
                }
            }
        }
        Ok(changed)
    }
}

/// The reduced static shapes that give prescribed displacements u at the pROM's inputs:
/// q = K_r⁻¹ S_r (S_rᵀ K_r⁻¹ S_r)⁻¹ u, the reduced displacement under input forces only, whose
/// input displacements S_rᵀ q equal u. Both factorizations are made once.
pub struct InputStaticShapes {
    /// K_r⁻¹ S_r (n × k).
    x: Mat<f64>,
    /// LU of the input flexibility S_rᵀ K_r⁻¹ S_r (k × k).
    flexibility: faer::linalg::solvers::PartialPivLu<f64>,
}

impl InputStaticShapes {
    /// Factor K_r and the input flexibility of the inputs S_r (n × k).
    pub fn new(k_r: MatRef<'_, f64>, s_r: &Mat<f64>) -> Self {
        let x = k_r.partial_piv_lu().solve(s_r);
        let flexibility = (s_r.transpose() * &x).partial_piv_lu();
        InputStaticShapes { x, flexibility }
    }

    /// The shape q (length n) of input displacements `u` (length k); `None` when K_r or the
    /// input flexibility is singular (the shape is not finite).
    pub fn shape(&self, u: &[f64]) -> Option<Vec<f64>> {
        let u = Mat::<f64>::from_fn(u.len(), 1, |i, _| u[i]);
        let q = &self.x * self.flexibility.solve(&u);
        let q: Vec<f64> = (0..q.nrows()).map(|i| q[(i, 0)]).collect();
        q.iter().all(|x| x.is_finite()).then_some(q)
    }
}
