//! System coordinates (thesis eq. 2.44–2.45, DESIGN.md §11): body i owns the slice
//! qⁱ = [r (3), e (4), q_f (n_r)] of q, placed one after the other in the order the bodies were
//! added; a rigid body has n_r = 0 and the ground (body `None`) has no coordinates. The
//! velocity vector v = q̇ has the same layout.

use faer::{MatMut, MatRef};

/// Where one body's coordinates sit in the system vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodySlice {
    /// Index of r₁ in q.
    pub offset: usize,
    /// Number of flexible coordinates n_r.
    pub modes: usize,
}

impl BodySlice {
    /// 7 + n_r.
    pub fn len(&self) -> usize {
        7 + self.modes
    }
    /// Always false (a body has at least r and e); present for clippy's `len` rule.
    pub fn is_empty(&self) -> bool {
        false
    }
    /// Index of e₀ in q.
    pub fn euler(&self) -> usize {
        self.offset + 3
    }
    /// Index of the first flexible coordinate in q.
    pub fn flexible(&self) -> usize {
        self.offset + 7
    }
    /// r of this body in q.
    pub fn position(&self, q: &[f64]) -> [f64; 3] {
        [q[self.offset], q[self.offset + 1], q[self.offset + 2]]
    }
    /// e of this body in q.
    pub fn euler_parameters(&self, q: &[f64]) -> [f64; 4] {
        let o = self.euler();
        [q[o], q[o + 1], q[o + 2], q[o + 3]]
    }
    /// q_f of this body in q.
    pub fn modal<'a>(&self, q: &'a [f64]) -> &'a [f64] {
        &q[self.flexible()..self.flexible() + self.modes]
    }
    /// Adds scale · `block` (n_r × n_r, e.g. K_ff) to the q_f–q_f block of `out` (system size).
    pub fn add_modal_block(&self, out: &mut MatMut<'_, f64>, block: MatRef<'_, f64>, scale: f64) {
        for i in 0..self.modes {
            for j in 0..self.modes {
                out[(self.flexible() + i, self.flexible() + j)] += scale * block[(i, j)];
            }
        }
    }
}

/// The slices of all bodies, in order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Layout {
    slices: Vec<BodySlice>,
    size: usize,
}

impl Layout {
    /// Appends a body with `modes` flexible coordinates and returns its slice.
    pub fn push(&mut self, modes: usize) -> BodySlice {
        let slice = BodySlice {
            offset: self.size,
            modes,
        };
        self.size += slice.len();
        self.slices.push(slice);
        slice
    }
    /// Number of coordinates n_sys.
    pub fn size(&self) -> usize {
        self.size
    }
    /// The slice of body `i`.
    pub fn slice(&self, i: usize) -> BodySlice {
        self.slices[i]
    }
    /// All slices in order.
    pub fn slices(&self) -> &[BodySlice] {
        &self.slices
    }
}
