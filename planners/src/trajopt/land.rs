//! Landing a window of a plan on the state its rest replays from: Gauss–Newton corrections of
//! least norm to the window's controls.
//!
//! A step of the optimiser lands a window on its target only to first order; the rest of the
//! plan replays chaotically from wherever the window ends, so the window is brought onto the
//! target to the flow's rounding ([`LANDING`]) before it is judged. The corrections use the
//! sensitivities of the step's own linearisation (the chord method: the step is small, so they
//! stay close), which costs one rollout of the window per correction.

use nalgebra::{DMatrix, DVector};

use super::linearise::EdgeJacobian;
use super::rollout::{End, LANDING, Rollout};
use crate::Problem;

/// The most corrections tried; each must shrink the miss.
const CORRECTIONS: usize = 12;

/// `rollout` after least-norm corrections of its controls that bring its end onto its target
/// (field angles in rad and gradients in fractions of the limit weighed alike); the rollout as
/// it was when its end is free or it already lands.
/// `model` is the window's linearisation at the iterate the step left from.
pub fn land(
    problem: &Problem,
    mut rollout: Rollout,
    model: &[EdgeJacobian],
    margin: f64,
) -> Rollout {
    let End::Land(target) = rollout.end.clone() else {
        return rollout;
    };
    let n = problem.agents();
    let dim = 2 * n;
    let limit = problem.model.coil.gradient_limit();
    let scale = [1.0, limit, limit];
    let miss = |r: &Rollout| -> DVector<f64> {
        let end = r.states.last().expect("the start");
        DVector::from_iterator(
            dim,
            end.iter()
                .zip(&target)
                .flat_map(|(p, t)| [p.x - t.x, p.y - t.y]),
        )
    };
    // J = ∂x_end/∂u, column by column from the last edge back: M_k = A_{K−1} … A_{k+1}
    let k_edges = rollout.edges();
    let mut j = DMatrix::zeros(dim, 3 * k_edges);
    let mut m = DMatrix::<f64>::identity(dim, dim);
    for k in (0..k_edges).rev() {
        let a = DMatrix::from_row_slice(dim, dim, &model[k].a);
        let b = DMatrix::from_row_slice(dim, 3, &model[k].b);
        let mb = &m * b;
        for (c, s) in scale.iter().enumerate() {
            j.set_column(3 * k + c, &(mb.column(c) * *s));
        }
        m *= a;
    }
    let gram = (&j * j.transpose()).lu();
    for _ in 0..CORRECTIONS {
        let e = miss(&rollout);
        if !rollout.valid || e.amax() <= LANDING / 2.0 || !e.iter().all(|x| x.is_finite()) {
            break;
        }
        let Some(lambda) = gram.solve(&(-&e)) else {
            break;
        };
        let step = j.transpose() * lambda;
        let delta: Vec<[f64; 3]> = (0..k_edges)
            .map(|k| std::array::from_fn(|c| step[3 * k + c] * scale[c]))
            .collect();
        let next = rollout.rerun(problem, rollout.stepped(&delta, limit), margin);
        if miss(&next).amax().partial_cmp(&e.amax()) != Some(std::cmp::Ordering::Less) {
            break;
        }
        rollout = next;
    }
    rollout
}
