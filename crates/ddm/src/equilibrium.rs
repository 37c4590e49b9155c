//! The independent check of a result: does every body's recovered field carry the contact
//! forces that the reported pressures say it does?

use crate::contact::Interface;

/// Per body, the equilibrium residual of the result: the contact forces that the recovered field
/// carries (T − D₀U at every contact point, since K u = f + N (T − D₀ Nᵀu)) against the penalty
/// forces w σ_n(s) of the reported pressures, ‖·‖₂ over the body's points relative to ‖w σ_n‖₂
/// over all points (with friction, the tangential tractions' forces too). Zero at a fixed point
/// of the iteration, whatever stopped it.
pub fn equilibrium(interface: &Interface, un: &[f64], t_load: &[f64]) -> Vec<f64> {
    let mut s = vec![0.0; un.len()];
    interface.sum_normal(un, &mut s);
    let g = interface.slip_sums(un);
    let force = |j: usize| interface.total_force(j, &s, &g);
    let total = (0..un.len()).map(|j| force(j).powi(2)).sum::<f64>().sqrt();
    interface
        .body_range
        .iter()
        .map(|range| {
            let residual = range
                .clone()
                .map(|j| {
                    let p = &interface.points[j];
                    (t_load[j] - p.spring * un[j] - force(j)).powi(2)
                })
                .sum::<f64>()
                .sqrt();
            if residual == 0.0 {
                0.0
            } else {
                residual / total
            }
        })
        .collect()
}
