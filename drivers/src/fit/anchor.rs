//! What fixes the moment/drag/gain scale when the data do not, and the standard errors of the
//! moments, drags and gains relative to it: their contrasts with the anchor, which a move
//! along the scale leaves unchanged.

use super::model::{Kind, Model, Segment};
use super::problem::Problem;
use super::report::Status;

/// What fixes the moment/drag/gain scale when the data do not.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Anchor {
    /// The convention: the moments' geometric mean at 1.
    Convention,
    /// A moment, drag or gain the fit set aside (unidentified or imprecise), held where the
    /// data do not confirm it: the first in the parameters' order when several were.
    SetAside(usize),
}

impl Anchor {
    /// The anchor when the scale is held by a moment, drag or gain the fit set aside; `None`
    /// when the user held one (`--hold`, a measured value), which fixes it.
    pub(super) fn set_aside(
        kinds: &[Kind],
        user_held: &[bool],
        set_aside: &[(usize, Status)],
    ) -> Option<Self> {
        let scale: Vec<usize> = (0..kinds.len())
            .filter(|&i| scale_power(&kinds[i]) != 0.0)
            .collect();
        if scale.iter().any(|&i| user_held[i]) {
            return None;
        }
        scale
            .into_iter()
            .find(|&i| set_aside.iter().any(|u| u.0 == i))
            .map(Anchor::SetAside)
    }

    /// The anchor's `ln λ` as a combination of the parameters: moved along the scale
    /// direction `dir` by `t`, it moves by `t`.
    pub(super) fn ln_scale(&self, kinds: &[Kind], dir: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; kinds.len()];
        match *self {
            Anchor::Convention => {
                let moments: Vec<usize> = (0..kinds.len())
                    .filter(|&i| matches!(kinds[i], Kind::Moment(_)))
                    .collect();
                let sum: f64 = moments.iter().map(|&i| dir[i]).sum();
                for i in moments {
                    r[i] = 1.0 / sum;
                }
            }
            Anchor::SetAside(h) => r[h] = 1.0 / dir[h],
        }
        r
    }
}

/// The standard errors of the fitted moments, drags and gains relative to what fixes their
/// scale when the data do not ([`Anchor`], none held by the user): those of their
/// [`contrasts`] with it, from the data alone, every moment, drag and gain free and without
/// the convention's row. A term that breaks the scale only weakly bends the direction the data
/// do not see away from the scale alone: an anchor held where the data do not confirm it then
/// moves the other values with it, which the standard errors of the fit with the anchor held
/// do not show. Where no term breaks the scale these equal the held fit's.
pub(super) fn relative_standard_errors(
    model: &Model,
    segs: &[Segment],
    problem: &Problem<'_>,
    free: &[bool],
    anchor: &Anchor,
    free_starts: bool,
) -> Vec<(usize, f64)> {
    let (fitted, combos) = contrasts(&model.kinds, free, anchor);
    // every moment, drag and gain free: no held one fixes the scale
    let unanchored: Vec<bool> = (0..model.kinds.len())
        .map(|i| free[i] || scale_power(&model.kinds[i]) != 0.0)
        .collect();
    let p = Problem::new(
        model,
        segs.to_vec(),
        problem.x().to_vec(),
        unanchored,
        free_starts,
    );
    fitted
        .into_iter()
        .zip(p.combination_standard_errors(&combos))
        .collect()
}

/// [`Kind::scale_power`] as a direction's coordinate.
pub(super) fn scale_power(kind: &Kind) -> f64 {
    f64::from(kind.scale_power())
}

/// The free moments, drags and gains, each with its contrast against `anchor`,
/// `x_i − p_i·t(x)` (`p_i` its power of λ, `t` the anchor's `ln λ`), as a combination of every
/// parameter: a move along the scale leaves it as it is.
pub(super) fn contrasts(
    kinds: &[Kind],
    free: &[bool],
    anchor: &Anchor,
) -> (Vec<usize>, Vec<Vec<f64>>) {
    let dir: Vec<f64> = kinds.iter().map(scale_power).collect();
    let t = anchor.ln_scale(kinds, &dir);
    let fitted: Vec<usize> = (0..kinds.len())
        .filter(|&i| free[i] && dir[i] != 0.0)
        .collect();
    let combos = fitted
        .iter()
        .map(|&i| {
            let mut a: Vec<f64> = t.iter().map(|w| -dir[i] * w).collect();
            a[i] += 1.0;
            a
        })
        .collect();
    (fitted, combos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::scale_direction;

    /// Moments, drags and gains of two agents, then the field bias.
    fn kinds() -> Vec<Kind> {
        vec![
            Kind::Moment(0),
            Kind::Drag(0),
            Kind::Moment(1),
            Kind::Drag(1),
            Kind::GradientGain(0),
            Kind::GradientGain(1),
            Kind::FieldBias,
        ]
    }

    #[test]
    fn a_contrast_with_either_anchor_does_not_move_along_the_scale() {
        let kinds = kinds();
        let dir = scale_direction(&kinds, &[true; 7]).unwrap();
        let mut set_aside = [true; 7];
        set_aside[3] = false;
        for (anchor, free, want) in [
            (Anchor::Convention, [true; 7], vec![0, 1, 2, 3, 4, 5]),
            (Anchor::SetAside(3), set_aside, vec![0, 1, 2, 4, 5]),
        ] {
            let t = anchor.ln_scale(&kinds, &dir);
            // the anchor's ln λ moves with the scale at rate 1
            let rate: f64 = t.iter().zip(&dir).map(|(a, b)| a * b).sum();
            assert!((rate - 1.0).abs() < 1e-12, "{anchor:?}: {rate}");
            let (fitted, combos) = contrasts(&kinds, &free, &anchor);
            assert_eq!(fitted, want, "{anchor:?}");
            for (i, a) in fitted.iter().zip(&combos) {
                let along: f64 = a.iter().zip(&dir).map(|(a, b)| a * b).sum();
                assert!(along.abs() < 1e-12, "{anchor:?}, {:?}: {along}", kinds[*i]);
                assert!(a[*i] > 0.0 && a[6] == 0.0, "{anchor:?}: {a:?}");
            }
        }
    }

    #[test]
    fn the_anchor_is_the_first_scale_value_set_aside_unless_the_user_held_one() {
        let kinds = kinds();
        let none = [false; 7];
        let aside = [
            (6, Status::Unidentified(0.1)),
            (3, Status::Imprecise(0.2)),
            (5, Status::Unidentified(0.3)),
        ];
        assert_eq!(
            Anchor::set_aside(&kinds, &none, &aside),
            Some(Anchor::SetAside(3))
        );
        let mut user = none;
        user[5] = true;
        assert_eq!(Anchor::set_aside(&kinds, &user, &aside), None);
        assert_eq!(Anchor::set_aside(&kinds, &none, &aside[..1]), None);
    }
}
