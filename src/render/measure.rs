//! Measures of a method's image against the truth, over the pixels the surface covers
//! entirely (silhouette pixels are left out: a one-sample shader aliases there whatever
//! its filter, and that is not what these figures judge).
//!
//! - MSE of the linear radiance and the relative MSE Σ(m − t)²/Σt², each without the
//!   truth's noise (from its two replicates, [`errors`]) ± the s.e. that noise leaves,
//!   and the truth's noise floor √(mean s.e.²) beside them.
//! - ꟻLIP (NVIDIA, LDR, through `nv-flip`) on the tone-mapped images against the truth
//!   image as rendered, its mean ± s.e. over pixels.
//! - Flicker along a camera path ([`flicker`]): the mean absolute frame-to-frame change of
//!   the displayed value, the method's mean squared change minus the truth's and the
//!   temporal MSE mean((Δm − Δt)²), the truth's terms from its replicates; s.e. over the
//!   frame pairs.
//!
//! One tone map everywhere: exposure, then Reinhard x/(1 + x), then the sRGB curve.

use super::truth::PixelTruth;
use serde::Serialize;

pub use crate::integrate::Figure;

/// The displayed value in [0, 1] of a linear radiance.
pub fn tone(x: f64, exposure: f64) -> f64 {
    let y = (x * exposure).max(0.0);
    let y = if y.is_finite() { y / (1.0 + y) } else { 1.0 };
    if y <= 0.0031308 {
        12.92 * y
    } else {
        1.055 * y.powf(1.0 / 2.4) - 0.055
    }
}

/// An image's measures against the truth.
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Measures {
    /// Mean squared error over the covered pixels, unbiased for the error against the
    /// exact image ([`errors`]), ± the standard error the truth's noise leaves on it.
    pub mse: Figure,
    /// The same over the mean squared truth (a ratio: its second-order bias is added to
    /// the bar).
    pub rel_mse: Figure,
    /// Mean ꟻLIP against the truth image as rendered (its noise included), ± the s.e. over
    /// pixels.
    pub flip: Figure,
    /// The truth's noise floor √(mean s.e.²) over the same pixels.
    #[serde(deserialize_with = "crate::integrate::estimate::f64_or_nan")]
    pub truth_noise: f64,
    pub pixels: usize,
}

/// The mask of pixels the surface covers entirely.
pub fn mask(truth: &[PixelTruth]) -> Vec<bool> {
    truth.iter().map(|t| t.covered).collect()
}

/// MSE, relative MSE and the truth's noise floor of `img` against `truth`, over the
/// covered pixels.
///
/// Each truth pixel is the mean v of two independent replicates r₁, r₂ with s = |r₁ − r₂|/2,
/// so (m − r₁)(m − r₂) = (m − v)² − s² is unbiased for the squared error against the
/// exact pixel t (E[(m − r₁)(m − r₂)] = (m − t)²), and r₁r₂ = v² − s² for t²: the MSE
/// and the mean squared truth are means of unbiased per-pixel terms. Their standard
/// errors come from the truth's noise alone (the pixels are the measured set, not a
/// sample of one): with σ₁² a replicate's variance, Var[(m − r₁)(m − r₂)] = 2(m − t)²σ₁² +
/// σ₁⁴ and Var[r₁r₂] = 2t²σ₁² + σ₁⁴ per pixel, whose unbiased estimates are 4(m − v)²s²
/// and 4v²s² when the replicates' noise is Gaussian (v and r₁ − r₂ are then independent,
/// E[s²] = σ₁²/2): each replicate is a mean of many samples.
/// The relative MSE is their ratio: its bar is the delta-method s.e. plus the ratio's
/// second-order bias bound R·(s.e.(D)/D)².
pub fn errors(truth: &[PixelTruth], img: &[f32]) -> (Figure, Figure, f64, usize) {
    let (mut a, mut va, mut d, mut vd, mut s2, mut count) = (0.0, 0.0, 0.0, 0.0, 0.0, 0);
    for (t, &m) in truth.iter().zip(img).filter(|(t, _)| t.covered) {
        count += 1;
        let e = m as f64 - t.value;
        let s = t.diff * t.diff;
        a += e * e - s;
        d += t.value * t.value - s;
        va += 4.0 * e * e * s;
        vd += 4.0 * t.value * t.value * s;
        s2 += s;
    }
    if count == 0 {
        return (Figure::NONE, Figure::NONE, f64::NAN, 0);
    }
    let n = count as f64;
    let (mse, den) = (a / n, d / n);
    let (se_a, se_d) = (va.sqrt() / n, vd.sqrt() / n);
    let rel = if den > 0.0 {
        let r = mse / den;
        let delta = (se_a * se_a + r * r * se_d * se_d).sqrt() / den;
        Figure::with_se(r, delta + r.abs() * (se_d / den).powi(2))
    } else {
        Figure::NONE
    };
    (Figure::with_se(mse, se_a), rel, (s2 / n).sqrt(), count)
}

/// 8-bit sRGB (grey) of a linear image after the tone map.
pub fn to_rgb8(img: &[f64], exposure: f64) -> Vec<u8> {
    img.iter()
        .flat_map(|&x| {
            let v = (tone(x, exposure) * 255.0).round().clamp(0.0, 255.0) as u8;
            [v, v, v]
        })
        .collect()
}

/// ꟻLIP of `test` against `reference` (both linear, tone-mapped here): the per-pixel
/// error map and its mean ± s.e. over the mask.
pub fn flip(
    reference: &[f64],
    test: &[f64],
    w: usize,
    h: usize,
    exposure: f64,
    on: &[bool],
) -> (Vec<f32>, Figure) {
    let r = nv_flip::FlipImageRgb8::with_data(w as u32, h as u32, &to_rgb8(reference, exposure));
    let t = nv_flip::FlipImageRgb8::with_data(w as u32, h as u32, &to_rgb8(test, exposure));
    let e = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let vals: Vec<f64> = e
        .iter()
        .zip(on)
        .filter(|(_, m)| **m)
        .map(|(v, _)| *v as f64)
        .collect();
    (e, Figure::mean_of(&vals))
}

/// Flicker of a frame sequence against the truth's, on displayed values, over the pixels
/// covered in both frames of each pair; each figure the mean over frame pairs ± its s.e.
///
/// The truth's change Δt is noisy, so nothing here is a function of |Δt| or of Δt²: with
/// its two independent replicates a and b (`PixelTruth::diff`), Δt_a·Δt_b estimates the
/// truth's squared change and (Δm − Δt_a)(Δm − Δt_b) the squared difference without the
/// noise's bias (what remains is the tone map's curvature over the replicates' spread).
#[derive(Clone, Copy, Debug, Serialize, serde::Deserialize)]
pub struct Flicker {
    /// Mean |frame-to-frame change| of the method (no truth involved).
    pub change: Figure,
    /// The method's mean squared change minus the truth's.
    pub excess: Figure,
    /// Mean squared difference between the method's change and the truth's.
    pub temporal_mse: Figure,
}

/// The truth's own mean squared frame-to-frame change (Δt_a·Δt_b), over frame pairs.
pub fn truth_change(truth: &[&[PixelTruth]], exposure: f64) -> Figure {
    let mut v = Vec::new();
    for k in 1..truth.len() {
        let (t0, t1) = (truth[k - 1], truth[k]);
        let (mut s, mut n) = (0.0, 0usize);
        for p in 0..t0.len().min(t1.len()) {
            if t0[p].covered && t1[p].covered {
                let (a, b) = replicate_changes(&t0[p], &t1[p], exposure);
                s += a * b;
                n += 1;
            }
        }
        v.push(s / n.max(1) as f64);
    }
    Figure::mean_of(&v)
}

/// The displayed change of replicate a and of replicate b between two truth frames.
fn replicate_changes(t0: &PixelTruth, t1: &PixelTruth, exposure: f64) -> (f64, f64) {
    let tn = |x: f64| tone(x, exposure);
    (
        tn(t1.value + t1.diff) - tn(t0.value + t0.diff),
        tn(t1.value - t1.diff) - tn(t0.value - t0.diff),
    )
}

pub fn flicker(truth: &[&[PixelTruth]], frames: &[&[f32]], exposure: f64) -> Flicker {
    let mut change = Vec::new();
    let mut excess = Vec::new();
    let mut tmse = Vec::new();
    for k in 1..frames.len().min(truth.len()) {
        let (t0, t1, m0, m1) = (truth[k - 1], truth[k], frames[k - 1], frames[k]);
        let (mut c, mut e, mut s, mut n) = (0.0, 0.0, 0.0, 0usize);
        for p in 0..t0.len() {
            if !(t0[p].covered && t1[p].covered) {
                continue;
            }
            let dm = tone(m1[p] as f64, exposure) - tone(m0[p] as f64, exposure);
            let (da, db) = replicate_changes(&t0[p], &t1[p], exposure);
            c += dm.abs();
            e += dm * dm - da * db;
            s += (dm - da) * (dm - db);
            n += 1;
        }
        let n = n.max(1) as f64;
        change.push(c / n);
        excess.push(e / n);
        tmse.push(s / n);
    }
    Flicker {
        change: Figure::mean_of(&change),
        excess: Figure::mean_of(&excess),
        temporal_mse: Figure::mean_of(&tmse),
    }
}

/// One method's measures in one view, with its ꟻLIP map.
#[derive(Clone, Debug)]
pub struct Scored {
    pub key: String,
    pub label: String,
    pub m: Measures,
    pub flip_map: Vec<f32>,
}

/// Every view's scores and, along a camera path, every method's flicker and the truth's
/// own mean squared change.
#[derive(Clone, Debug)]
pub struct Measured {
    pub views: Vec<Vec<Scored>>,
    pub flicker: Vec<(String, String, Flicker)>,
    pub truth_change: Option<Figure>,
}

pub fn measure_render(r: &super::Render) -> Measured {
    let exp = r.scene.render.exposure;
    let views = r
        .views
        .iter()
        .map(|v| {
            let on = mask(&v.truth);
            let t: Vec<f64> = v.truth.iter().map(|p| p.value).collect();
            v.methods
                .iter()
                .map(|mi| {
                    let (mse, rel_mse, noise, pixels) = errors(&v.truth, &mi.pixels);
                    let test: Vec<f64> = mi.pixels.iter().map(|&x| x as f64).collect();
                    let (flip_map, flip) = flip(&t, &test, r.width, r.height, exp, &on);
                    Scored {
                        key: mi.key.clone(),
                        label: mi.label.clone(),
                        m: Measures {
                            mse,
                            rel_mse,
                            flip,
                            truth_noise: noise,
                            pixels,
                        },
                        flip_map,
                    }
                })
                .collect()
        })
        .collect();
    let (mut fl, mut truth_change) = (Vec::new(), None);
    if r.scene.frames() > 1 {
        let truths: Vec<&[PixelTruth]> = r.views.iter().map(|v| v.truth.as_slice()).collect();
        truth_change = Some(self::truth_change(&truths, exp));
        for (i, mi) in r.views[0].methods.iter().enumerate() {
            let frames: Vec<&[f32]> = r
                .views
                .iter()
                .map(|v| v.methods[i].pixels.as_slice())
                .collect();
            fl.push((
                mi.key.clone(),
                mi.label.clone(),
                flicker(&truths, &frames, exp),
            ));
        }
    }
    Measured {
        views,
        flicker: fl,
        truth_change,
    }
}
