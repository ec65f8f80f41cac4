//! Correlations (seed 004 §8.1): what Hypothesis 1's separation of colour, normals and
//! visibility costs on a height field where they are tied together.
//!
//! - Colour and reflectance (§8.1.2): colour k_x = 0.9 on flat texels (|∇h| < 0.05) and 0.1
//!   on slopes. Joint: Σ ŵ k_x ρ_x(l, v); separated: (Σ ŵ k_x)(Σ ŵ ρ_x(l, v)).
//! - Reflectance and visibility (§8.1.4): joint Σ ŵ V_x(l)V_x(v) ρ_x / Σ ŵ V_x(v);
//!   separated: the exact V_A(l, v) of Eq 23 times Σ ŵ ρ_x.
//!
//! ρ_x is the cosine-weighted GGX/Beckmann lobe about each texel's normal; the cost is the
//! relative L2 distance over the light hemisphere, by a Gauss–Legendre product in
//! (elevation, azimuth) with the horizons cached per azimuth.

use super::horizon::{horizon, Dir};
use super::HeightField;
use crate::error::Result;
use crate::integrate::quad::gauss_legendre;
use crate::microfacet::lobe::{lobe, Frame};
use crate::microfacet::{Microsurface, NdfKind, Roughness};
use nalgebra::Vector3;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// The colour of §8.1.2's example tied to slope.
pub fn colour(hf: &HeightField, i: usize, j: usize) -> f64 {
    let (gx, gy) = hf.gradient(i, j);
    if (gx * gx + gy * gy).sqrt() < 0.05 {
        0.9
    } else {
        0.1
    }
}

/// A direction's world vector.
pub fn world(d: &Dir) -> V3 {
    V3::new(
        d.elev.cos() * d.azim.cos(),
        d.elev.cos() * d.azim.sin(),
        d.elev.sin(),
    )
}

/// Relative L2 distances (colour–slope, visibility–normal) of the separated forms from the
/// joint ones for view v over the footprint, with `ne` × 2`ne` light directions.
pub fn separation_cost(
    hf: &HeightField,
    texels: &[(usize, usize)],
    kind: NdfKind,
    alpha: f64,
    v: &Dir,
    ne: usize,
) -> Result<(f64, f64)> {
    let s = Microsurface::new(kind, Roughness::iso(alpha)?);
    let frames: Vec<Frame> = texels
        .iter()
        .map(|&(i, j)| Frame::around(hf.normal(i, j)))
        .collect();
    let k: Vec<f64> = texels.iter().map(|&(i, j)| colour(hf, i, j)).collect();
    let n = texels.len() as f64;
    let kbar = k.iter().sum::<f64>() / n;
    let vv: Vec<f64> = texels
        .iter()
        .map(|&(i, j)| (v.elev > horizon(hf, i, j, v.azim)) as u8 as f64)
        .collect();
    let svv: f64 = vv.iter().sum();
    let vw = world(v);
    let (xe, we) = gauss_legendre(ne);
    let na = 2 * ne;
    let (mut c_num, mut c_den, mut v_num, mut v_den) = (0.0, 0.0, 0.0, 0.0);
    for ai in 0..na {
        let az = 2.0 * PI * (ai as f64 + 0.5) / na as f64;
        let hor: Vec<f64> = texels.iter().map(|&(i, j)| horizon(hf, i, j, az)).collect();
        for (x, w) in xe.iter().zip(&we) {
            let e = 0.25 * PI * (x + 1.0);
            let l = Dir { elev: e, azim: az };
            let lw = world(&l);
            let dw = w * 0.25 * PI * e.cos() * 2.0 * PI / na as f64;
            let rho: Vec<f64> = frames.iter().map(|f| lobe(&s, f, &vw, &lw)).collect();
            let rbar = rho.iter().sum::<f64>() / n;
            let joint_c = rho.iter().zip(&k).map(|(r, c)| r * c).sum::<f64>() / n;
            let sep_c = kbar * rbar;
            c_num += dw * (joint_c - sep_c).powi(2);
            c_den += dw * joint_c * joint_c;
            if svv > 0.0 {
                let vl: Vec<f64> = hor.iter().map(|t| (e > *t) as u8 as f64).collect();
                let joint_v = (0..texels.len())
                    .map(|t| vl[t] * vv[t] * rho[t])
                    .sum::<f64>()
                    / svv;
                let val = (0..texels.len()).map(|t| vl[t] * vv[t]).sum::<f64>() / svv;
                let sep_v = val * rbar;
                v_num += dw * (joint_v - sep_v).powi(2);
                v_den += dw * joint_v * joint_v;
            }
        }
    }
    let rel = |a: f64, b: f64| if b > 0.0 { (a / b).sqrt() } else { f64::NAN };
    Ok((rel(c_num, c_den), rel(v_num, v_den)))
}
