//! Recovery of the g-set solution and of the SPC forces.
//!
//! ```text
//! u_n = [u_f ; u_s]   (scattered by the f / s positions in n; u_s the enforced values)
//! u_g = T u_n         (u_m = G_mn u_n for the dependent DOFs)
//! q_s = (K_nn u_n − P_n)[s]        SPC forces (reactions) in the global frames
//! ```

use super::assemble::AffineOperator;
use super::constraints::RigidElimination;
use super::dofs::Sets;
use super::error::AssemblyError;

/// u_n from u_f and the g-set enforced values.
pub fn expand_f_to_n(
    u_f: &[f64],
    sets: &Sets,
    enforced: &[f64],
) -> Result<Vec<f64>, AssemblyError> {
    let mut u_n = vec![0.0; sets.n.len()];
    sets.f_in_n.scatter_into(u_f, &mut u_n)?;
    let u_s = sets.s.gather(enforced)?;
    sets.s_in_n.scatter_into(&u_s, &mut u_n)?;
    Ok(u_n)
}

/// u_g = T u_n with u_n from [`expand_f_to_n`].
pub fn recover_g(
    u_f: &[f64],
    sets: &Sets,
    enforced: &[f64],
    rigid: &RigidElimination,
) -> Result<Vec<f64>, AssemblyError> {
    rigid.expand(&expand_f_to_n(u_f, sets, enforced)?)
}

/// SPC forces q_s = (K_nn u_n − P_n)\[s\], in s-set order ([`Sets::s`] members). `k_nn_values`
/// are K_nn at the solved parameters, `p_n` = Tᵀ P_g.
pub fn spc_forces(
    k_nn: &AffineOperator,
    k_nn_values: &[f64],
    u_n: &[f64],
    p_n: &[f64],
    sets: &Sets,
) -> Result<Vec<f64>, AssemblyError> {
    let mut r = k_nn.mul_values(k_nn_values, u_n)?;
    super::dofs::check_len("P_n", r.len(), p_n.len())?;
    r.iter_mut().zip(p_n).for_each(|(a, b)| *a -= b);
    sets.s_in_n.gather(&r)
}
