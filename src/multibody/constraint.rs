//! Scalar holonomic constraints Φ(q, t) = 0 of two kinds: the Euler-parameter normalization
//! eᵀe − 1 of one body, and sums of time-weighted dot products of body vectors,
//!
//! ```text
//! Φ(q, t) = Σ_terms c(t) U(q) · W(q) + c₀(t),   U = Σᵢ sᵢ uᵢ(q) (+ constant), W likewise
//! ```
//!
//! which cover the joint primitives (coincident points, perpendicular directions, a direction
//! perpendicular to a separation) and the rheonomic drives (c(t) = cos θ_d(t), −sin θ_d(t),
//! c₀ = −s_d(t)). For each the module gives Φ, the Jacobian row Φ_q, Φ_t, the derivative of
//! Φ_t with respect to q and the weighted Hessian λ ∇²Φ:
//!
//! ```text
//! ∇(c U·W) = c (Wᵀ J_U + Uᵀ J_W),
//! ∇²(c U·W) = c (J_Uᵀ J_W + J_Wᵀ J_U + Σᵢ sᵢ ∇²(W·uᵢ) + Σⱼ sⱼ ∇²(U·wⱼ))
//! ```
//!
//! with the body-vector derivatives of [`super::vectors`].

use super::layout::Layout;
use super::rotations::Rotations;
use super::signal::Signal;
use super::vectors::BodyVector;

/// A linear combination of body vectors plus a constant vector.
#[derive(Debug, Clone, Default)]
pub struct VectorSum {
    pub parts: Vec<(f64, BodyVector)>,
    pub constant: [f64; 3],
}

impl VectorSum {
    /// One body vector.
    pub fn of(v: BodyVector) -> Self {
        Self {
            parts: vec![(1.0, v)],
            constant: [0.0; 3],
        }
    }
    /// a − b.
    pub fn difference(a: BodyVector, b: BodyVector) -> Self {
        Self {
            parts: vec![(1.0, a), (-1.0, b)],
            constant: [0.0; 3],
        }
    }
    /// A constant vector.
    pub fn constant(c: [f64; 3]) -> Self {
        Self {
            parts: Vec::new(),
            constant: c,
        }
    }

    fn value(&self, layout: &Layout, q: &[f64]) -> [f64; 3] {
        let mut out = self.constant;
        for (s, v) in &self.parts {
            let x = v.value(layout, q);
            for i in 0..3 {
                out[i] += s * x[i];
            }
        }
        out
    }

    fn value_rotated(&self, layout: &Layout, q: &[f64], rotations: &Rotations) -> [f64; 3] {
        let mut out = self.constant;
        for (s, v) in &self.parts {
            let x = v.value_rotated(layout, q, rotations.of(v.body));
            for i in 0..3 {
                out[i] += s * x[i];
            }
        }
        out
    }

    /// Calls `sink(j, gᵀ ∂U/∂q_j)`.
    fn contracted_jacobian(
        &self,
        layout: &Layout,
        q: &[f64],
        rotations: &Rotations,
        g: [f64; 3],
        sink: &mut impl FnMut(usize, f64),
    ) {
        for (s, v) in &self.parts {
            let sg = g.map(|x| s * x);
            v.contracted_jacobian(layout, q, rotations.of(v.body), sg, &mut *sink);
        }
    }

    fn jacobian(&self, layout: &Layout, q: &[f64], sink: &mut impl FnMut(usize, usize, f64)) {
        for (s, v) in &self.parts {
            v.jacobian(layout, q, |i, j, x| sink(i, j, s * x));
        }
    }

    fn hessian(
        &self,
        layout: &Layout,
        q: &[f64],
        w: [f64; 3],
        scale: f64,
        sink: &mut impl FnMut(usize, usize, f64),
    ) {
        for (s, v) in &self.parts {
            v.hessian(layout, q, w, |i, j, x| sink(i, j, scale * s * x));
        }
    }
}

/// A time-dependent weight of a dot-product term.
#[derive(Debug, Clone)]
pub enum Weight {
    /// c
    Constant(f64),
    /// cos(θ₀ + f(t))
    CosOf(f64, Signal),
    /// −sin(θ₀ + f(t))
    NegSinOf(f64, Signal),
    /// −(x₀ + f(t))
    NegOf(f64, Signal),
}

impl Weight {
    /// [c, ċ, c̈] at t.
    pub fn at(&self, t: f64) -> [f64; 3] {
        match self {
            Weight::Constant(c) => [*c, 0.0, 0.0],
            Weight::CosOf(x0, f) => {
                let [x, xd, xdd] = f.at(t);
                let (s, c) = (x0 + x).sin_cos();
                [c, -s * xd, -c * xd * xd - s * xdd]
            }
            Weight::NegSinOf(x0, f) => {
                let [x, xd, xdd] = f.at(t);
                let (s, c) = (x0 + x).sin_cos();
                [-s, -c * xd, s * xd * xd - c * xdd]
            }
            Weight::NegOf(x0, f) => {
                let [x, xd, xdd] = f.at(t);
                [-(x0 + x), -xd, -xdd]
            }
        }
    }
}

/// One term c(t) U · W.
#[derive(Debug, Clone)]
pub struct DotTerm {
    pub weight: Weight,
    pub u: VectorSum,
    pub w: VectorSum,
}

impl DotTerm {
    /// Calls `sink(j, c ∂(U·W)/∂q_j)` = c (Wᵀ ∂U/∂q_j + Uᵀ ∂W/∂q_j) at the values U = u, W = w.
    #[allow(clippy::too_many_arguments)]
    fn add_gradient(
        &self,
        layout: &Layout,
        q: &[f64],
        rotations: &Rotations,
        c: f64,
        u: [f64; 3],
        w: [f64; 3],
        sink: &mut impl FnMut(usize, f64),
    ) {
        self.u
            .contracted_jacobian(layout, q, rotations, w.map(|x| c * x), sink);
        self.w
            .contracted_jacobian(layout, q, rotations, u.map(|x| c * x), sink);
    }
}

/// Calls `sink(j, ∂(eᵀe − 1)/∂q_j)` = 2 e on body `body`'s Euler parameters.
fn normalization_gradient(
    layout: &Layout,
    body: usize,
    q: &[f64],
    mut sink: impl FnMut(usize, f64),
) {
    let s = layout.slice(body);
    for (a, x) in s.euler_parameters(q).iter().enumerate() {
        sink(s.euler() + a, 2.0 * x);
    }
}

/// A scalar constraint (see module docs).
#[derive(Debug, Clone)]
pub enum Constraint {
    /// eᵀe − 1 of one body.
    Normalization { body: usize },
    /// Σ c U·W + c₀(t).
    Dots {
        terms: Vec<DotTerm>,
        offset: Option<Weight>,
    },
}

impl Constraint {
    /// A time-independent single dot product U · W.
    pub fn dot(u: VectorSum, w: VectorSum) -> Self {
        Constraint::Dots {
            terms: vec![DotTerm {
                weight: Weight::Constant(1.0),
                u,
                w,
            }],
            offset: None,
        }
    }

    /// The bodies whose coordinates the row depends on (each once, ascending): outside their
    /// slices of q the row of Φ_q and of ∂(Φ_q v + Φ_t)/∂q is zero.
    pub fn bodies(&self) -> Vec<usize> {
        let mut bodies: Vec<usize> = match self {
            Constraint::Normalization { body } => vec![*body],
            Constraint::Dots { terms, .. } => terms
                .iter()
                .flat_map(|term| term.u.parts.iter().chain(&term.w.parts))
                .filter_map(|(_, v)| v.body)
                .collect(),
        };
        bodies.sort_unstable();
        bodies.dedup();
        bodies
    }

    /// Φ(q, t).
    pub fn value(&self, layout: &Layout, q: &[f64], t: f64) -> f64 {
        match self {
            Constraint::Normalization { body } => {
                let e = layout.slice(*body).euler_parameters(q);
                e.iter().map(|x| x * x).sum::<f64>() - 1.0
            }
            Constraint::Dots { terms, offset } => {
                let sum: f64 = terms
                    .iter()
                    .map(|term| {
                        let (u, w) = (term.u.value(layout, q), term.w.value(layout, q));
                        term.weight.at(t)[0] * (u[0] * w[0] + u[1] * w[1] + u[2] * w[2])
                    })
                    .sum();
                sum + offset.as_ref().map_or(0.0, |c| c.at(t)[0])
            }
        }
    }

    /// ∂Φ/∂t.
    pub fn time_rate(&self, layout: &Layout, q: &[f64], t: f64) -> f64 {
        self.time_derivative(layout, q, t, 1)
    }

    /// ∂ᵏΦ/∂tᵏ at fixed q for k = `order` ∈ {1, 2} (the weights' ċ or c̈).
    pub fn time_derivative(&self, layout: &Layout, q: &[f64], t: f64, order: usize) -> f64 {
        match self {
            Constraint::Normalization { .. } => 0.0,
            Constraint::Dots { terms, offset } => {
                let sum: f64 = terms
                    .iter()
                    .map(|term| {
                        let (u, w) = (term.u.value(layout, q), term.w.value(layout, q));
                        term.weight.at(t)[order] * (u[0] * w[0] + u[1] * w[1] + u[2] * w[2])
                    })
                    .sum();
                sum + offset.as_ref().map_or(0.0, |c| c.at(t)[order])
            }
        }
    }

    /// Calls `sink(j, ∂Φ/∂q_j)`; `derivative` selects c (0, the Jacobian Φ_q) or ċ (1, the
    /// derivative of Φ_t with respect to q).
    pub fn jacobian(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        derivative: usize,
        sink: impl FnMut(usize, f64),
    ) {
        self.gradient(layout, q, t, &Rotations::at(layout, q), derivative, sink);
    }

    /// [`Constraint::jacobian`] with the bodies' rotations at q given.
    pub fn gradient(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        rotations: &Rotations,
        derivative: usize,
        mut sink: impl FnMut(usize, f64),
    ) {
        match self {
            Constraint::Normalization { body } => {
                if derivative == 0 {
                    normalization_gradient(layout, *body, q, sink);
                }
            }
            Constraint::Dots { terms, .. } => {
                for term in terms {
                    let c = term.weight.at(t)[derivative];
                    if c != 0.0 {
                        let u = term.u.value_rotated(layout, q, rotations);
                        let w = term.w.value_rotated(layout, q, rotations);
                        term.add_gradient(layout, q, rotations, c, u, w, &mut sink);
                    }
                }
            }
        }
    }

    /// Φ and Φ_t at (q, t), calling `sink(j, ∂Φ/∂q_j)` for Φ_q, in one pass with the
    /// bodies' rotations at q given.
    pub fn evaluate(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        rotations: &Rotations,
        mut sink: impl FnMut(usize, f64),
    ) -> [f64; 2] {
        match self {
            Constraint::Normalization { body } => {
                normalization_gradient(layout, *body, q, sink);
                [self.value(layout, q, t), 0.0]
            }
            Constraint::Dots { terms, offset } => {
                let mut out = offset.as_ref().map_or([0.0; 2], |c| {
                    let [x, xd, _] = c.at(t);
                    [x, xd]
                });
                for term in terms {
                    let [c, c_dot, _] = term.weight.at(t);
                    let u = term.u.value_rotated(layout, q, rotations);
                    let w = term.w.value_rotated(layout, q, rotations);
                    let dot = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
                    out[0] += c * dot;
                    out[1] += c_dot * dot;
                    if c != 0.0 {
                        term.add_gradient(layout, q, rotations, c, u, w, &mut sink);
                    }
                }
                out
            }
        }
    }

    /// Calls `sink(i, j, weight ∂²Φ/∂qᵢ∂q_j)` (entries may repeat; they add up).
    pub fn hessian(
        &self,
        layout: &Layout,
        q: &[f64],
        t: f64,
        weight: f64,
        mut sink: impl FnMut(usize, usize, f64),
    ) {
        match self {
            Constraint::Normalization { body } => {
                let e = layout.slice(*body).euler();
                for a in 0..4 {
                    sink(e + a, e + a, 2.0 * weight);
                }
            }
            Constraint::Dots { terms, .. } => {
                let mut ju = Vec::new();
                let mut jw = Vec::new();
                for term in terms {
                    let c = weight * term.weight.at(t)[0];
                    if c == 0.0 {
                        continue;
                    }
                    let (u, w) = (term.u.value(layout, q), term.w.value(layout, q));
                    ju.clear();
                    jw.clear();
                    term.u
                        .jacobian(layout, q, &mut |i, j, x| ju.push((i, j, x)));
                    term.w
                        .jacobian(layout, q, &mut |i, j, x| jw.push((i, j, x)));
                    for &(i, a, x) in &ju {
                        for &(k, b, y) in &jw {
                            if i == k {
                                sink(a, b, c * x * y);
                                sink(b, a, c * x * y);
                            }
                        }
                    }
                    term.u.hessian(layout, q, w, c, &mut sink);
                    term.w.hessian(layout, q, u, c, &mut sink);
                }
            }
        }
    }
}
