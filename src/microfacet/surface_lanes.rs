//! D and Smith Λ of a [`Microsurface`] for four directions at a time (`crate::lanes`):
//! GGX spelled out step by step across the lanes, so the four chains of divisions and
//! roots overlap; the other NDFs and Λ forms lane by lane through their scalar forms.
//! Each lane performs [`Microsurface::d_with`]'s and [`Microsurface::lambda`]'s
//! operations in their order, so its bits are theirs (tested in `microfacet::lobe`).

use super::surface::{g2_from_lambdas, Microsurface, NdfKind};
use crate::lanes::{map, quad2, Dirs, Lanes};

impl Microsurface {
    /// [`Microsurface::d_with`] of each lane of `m`, given `norm` = [`Self::d_norm`].
    #[inline(always)]
    pub fn d_lanes(&self, m: &Dirs, norm: f64) -> Lanes {
        if self.kind != NdfKind::Ggx {
            return map(|i| self.d_with(&m.get(i), norm));
        }
        let mean = &self.mean;
        let vx = map(|i| m.x[i] + mean.x * m.z[i]);
        let vy = map(|i| m.y[i] + mean.y * m.z[i]);
        let w = quad2(self.rough.inv(), &vx, &vy);
        map(|i| {
            let (mz, s) = (m.z[i], w[i] + m.z[i] * m.z[i]);
            if !(mz > 0.0) {
                0.0
            } else {
                norm / (s * s)
            }
        })
    }

    /// [`Microsurface::lambda`] of each lane of `o`: ν = (o_z − x̄·o_xy)/√(o_xyᵀ A o_xy),
    /// then GGX's Λ(ν) (+∞ where ν ≤ 0 or NaN).
    #[inline(always)]
    pub fn lambda_lanes(&self, o: &Dirs) -> Lanes {
        if self.kind != NdfKind::Ggx {
            return map(|i| self.lambda(&o.get(i)));
        }
        // a GGX surface's Λ is its exact one whatever its LambdaKind (`Self::lambda`)
        let mean = &self.mean;
        let num = map(|i| o.z[i] - mean.x * o.x[i] - mean.y * o.y[i]);
        let q = quad2(self.rough.a(), &o.x, &o.y);
        let den = map(|i| q[i].sqrt());
        let nu = map(|i| {
            if den[i] == 0.0 {
                if num[i] > 0.0 {
                    f64::INFINITY
                } else if num[i] < 0.0 {
                    f64::NEG_INFINITY
                } else {
                    0.0
                }
            } else {
                num[i] / den[i]
            }
        });
        map(|i| {
            if !(nu[i] > 0.0) {
                f64::INFINITY
            } else {
                super::lambda::ggx(nu[i])
            }
        })
    }
}

/// `Microsurface::g2_correlated` lane by lane from its pieces: 0 where i·m ≤ 0 or o·m ≤ 0,
/// else [`g2_from_lambdas`] of Λ(i) and Λ(o).
#[inline(always)]
pub fn g2_lanes(im: &Lanes, om: &Lanes, lambda_i: &Lanes, lambda_o: &Lanes) -> Lanes {
    map(|k| {
        if im[k] <= 0.0 || om[k] <= 0.0 {
            0.0
        } else {
            g2_from_lambdas(lambda_i[k], lambda_o[k])
        }
    })
}
