//! The compact LTC kernels (results/ltc-compact.md): per pixel, the six channels of an LTC
//! table (M⁻¹'s a, b, c, d; norm; fresnel) at (r, t) = (√α, √(1 − cos θ)), either
//!
//! - **texture-free**: evaluated from the compact Chebyshev series (`ltc::compact`;
//!   [`Compact::eval_f32`] is the scalar form), or
//! - **lookup**: read bilinearly from an n×n f32 texture holding the binary16 table rebuilt
//!   from the series, as a GPU's linear clamp-to-edge sampler reads it
//!   (`ltc::table::bilinear` is the f64 reference).
//!
//! Same inputs, same output layout (channel-major: `out[ch·len + i]`), so the two cost
//! the same work around them and their times compare. The AVX2 forms do the scalar forms'
//! operations in the same order, 8 pixels at a time, without fused multiply-adds: bit for
//! bit equal to them, except where a channel is stored as a logarithm (the lane-wise e^x
//! of `avx2::exp` against the scalar `f32::exp`; tests/kernels.rs states the bound).

#[cfg(target_arch = "x86_64")]
use super::avx2;
use super::dispatch::{check, Backend};
use crate::error::{Error, Result};
use crate::ltc::compact::Compact;
use crate::ltc::table::FittedTable;

/// A compact series as a shader holds it: f32 coefficients (p² per channel, Chebyshev
/// degree along r fastest), each channel's transform and the α floor.
#[derive(Clone, Debug)]
pub struct CompactF32 {
    series: Compact,
    coeffs: Vec<Vec<f32>>,
}

impl CompactF32 {
    /// A typed error for a series that fails its own check.
    pub fn of(c: &Compact) -> Result<CompactF32> {
        c.check()?;
        Ok(CompactF32 {
            series: c.clone(),
            coeffs: c.coeffs_f32(),
        })
    }
    pub fn p(&self) -> usize {
        self.series.p
    }
}

/// An n×n texture of six f32 channels (each channel a row-major n×n plane, texel (i, j) at
/// (r, t) = (i, j)/(n − 1)).
#[derive(Clone, Debug)]
pub struct TableF32 {
    pub n: usize,
    pub planes: [Vec<f32>; 6],
}

impl TableF32 {
    /// Side 2..=`MAX_SIDE` and every plane n² texels: what the lookup reads (its AVX2
    /// form gathers by computed index, so a short plane must never reach it).
    pub fn check(&self) -> Result<()> {
        let n = self.n;
        if !(2..=crate::ltc::table::MAX_SIDE).contains(&n)
            || self.planes.iter().any(|p| p.len() != n * n)
        {
            return Err(Error::InvalidArgument(format!(
                "lookup kernel: a table of side {n} with planes of {:?} texels (side 2..={}, n² each)",
                self.planes.iter().map(Vec::len).collect::<Vec<_>>(),
                crate::ltc::table::MAX_SIDE
            )));
        }
        Ok(())
    }

    /// The binary16 entries a table stores (every f16 file's texels), decoded to f32, as a
    /// sampler returns them. A typed error for a side below 2.
    pub fn of(t: &FittedTable) -> Result<TableF32> {
        let n = t.n;
        let half = t.half.as_ref().map_or(n * n, Vec::len);
        if n < 2 || t.cells.len() != n * n || half != n * n {
            return Err(Error::InvalidArgument(format!(
                "lookup kernel: a table of side {n} with {} cells and {half} binary16 cells (side ≥ 2, n² each)",
                t.cells.len()
            )));
        }
        let tab = TableF32 {
            n,
            planes: std::array::from_fn(|ch| {
                (0..n * n).map(|k| t.half_cell(k)[ch].to_f32()).collect()
            }),
        };
        tab.check()?;
        Ok(tab)
    }
}

/// Lengths equal, the output six times as long, every (r, t) finite: what both kernels
/// need (a NaN would clamp differently lane-wise and in the scalar form).
fn check_inputs(backend: Backend, r: &[f32], t: &[f32], out: &[f32]) -> Result<()> {
    check(backend, &[r.len(), t.len()], out.len() / 6)?;
    if out.len() != 6 * r.len() {
        return Err(Error::InvalidArgument(format!(
            "compact LTC kernel: output of {} for {} pixels (six channels each)",
            out.len(),
            r.len()
        )));
    }
    if let Some(x) = r.iter().chain(t).find(|x| !x.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "compact LTC kernel: input {x} (r and t must be finite)"
        )));
    }
    Ok(())
}

/// The pixels from `start` on (those the AVX2 form left): `at`, or for the per-pixel
/// backend its non-inlined twin `one`, written channel-major.
fn finish(
    backend: Backend,
    r: &[f32],
    t: &[f32],
    out: &mut [f32],
    start: usize,
    at: impl Fn(f32, f32) -> [f32; 6],
    one: impl Fn(f32, f32) -> [f32; 6],
) {
    let len = r.len();
    for i in start..len {
        let v = if backend == Backend::PerPixel {
            one(r[i], t[i])
        } else {
            at(r[i], t[i])
        };
        for (ch, x) in v.into_iter().enumerate() {
            out[ch * len + i] = x;
        }
    }
}

#[inline(never)]
fn one_series(s: &CompactF32, r: f32, t: f32) -> [f32; 6] {
    s.series.eval_f32(&s.coeffs, r, t)
}

/// The texture-free form: `out[ch·len + i]` = channel ch of the series at (r[i], t[i]).
pub fn ltc_compact_series(
    backend: Backend,
    s: &CompactF32,
    r: &[f32],
    t: &[f32],
    out: &mut [f32],
) -> Result<()> {
    check_inputs(backend, r, t, out)?;
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`.
        start = unsafe { simd::series(s, r, t, out) };
    }
    finish(
        backend,
        r,
        t,
        out,
        start,
        |a, b| s.series.eval_f32(&s.coeffs, a, b),
        |a, b| one_series(s, a, b),
    );
    Ok(())
}

/// One pixel's bilinear lookup in f32: `ltc::table::bilinear`'s operations.
#[inline(always)]
fn lookup_at(tab: &TableF32, r: f32, t: f32) -> [f32; 6] {
    let n = tab.n;
    let (x, y) = (
        r.clamp(0.0, 1.0) * (n - 1) as f32,
        t.clamp(0.0, 1.0) * (n - 1) as f32,
    );
    let (i0, j0) = (x.floor().min((n - 2) as f32), y.floor().min((n - 2) as f32));
    let (fx, fy) = (x - i0, y - j0);
    let k = i0 as usize + n * j0 as usize;
    std::array::from_fn(|ch| {
        let p = &tab.planes[ch];
        (p[k] * (1.0 - fx) + p[k + 1] * fx) * (1.0 - fy)
            + (p[k + n] * (1.0 - fx) + p[k + n + 1] * fx) * fy
    })
}

#[inline(never)]
fn one_lookup(tab: &TableF32, r: f32, t: f32) -> [f32; 6] {
    lookup_at(tab, r, t)
}

/// The texture: `out[ch·len + i]` = channel ch of the table read bilinearly at
/// (r[i], t[i]).
pub fn ltc_compact_lookup(
    backend: Backend,
    tab: &TableF32,
    r: &[f32],
    t: &[f32],
    out: &mut [f32],
) -> Result<()> {
    check_inputs(backend, r, t, out)?;
    tab.check()?;
    let mut start = 0;
    #[cfg(target_arch = "x86_64")]
    if backend == Backend::Avx2 {
        // SAFETY: avx2 and fma were detected at run time in `check`; `tab.check` holds
        // every plane to n² texels, so every gathered index (< n² − 1) is in bounds.
        start = unsafe { simd::lookup(tab, r, t, out) };
    }
    finish(
        backend,
        r,
        t,
        out,
        start,
        |a, b| lookup_at(tab, a, b),
        |a, b| one_lookup(tab, a, b),
    );
    Ok(())
}

#[cfg(target_arch = "x86_64")]
mod simd {
    use crate::kernels::compact::{CompactF32, TableF32};
    use crate::ltc::compact::Transform;
    use std::arch::x86_64::*;

    /// Σ c_k T_k(x) by Clenshaw, the scalar form's operations: b0 = (c_k + (x + x)·b1) − b2,
    /// then (c_0 + x·b1) − b2; `c` gives coefficient k as a vector.
    #[inline(always)]
    unsafe fn clenshaw(p: usize, c: impl Fn(usize) -> __m256, x: __m256) -> __m256 {
        let (mut b1, mut b2) = (_mm256_setzero_ps(), _mm256_setzero_ps());
        for k in (1..p).rev() {
            let b0 = _mm256_sub_ps(
                _mm256_add_ps(c(k), _mm256_mul_ps(_mm256_add_ps(x, x), b1)),
                b2,
            );
            b2 = b1;
            b1 = b0;
        }
        _mm256_sub_ps(_mm256_add_ps(c(0), _mm256_mul_ps(x, b1)), b2)
    }

    #[inline(always)]
    unsafe fn unit(v: __m256) -> __m256 {
        _mm256_min_ps(_mm256_max_ps(v, _mm256_setzero_ps()), _mm256_set1_ps(1.0))
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn series(s: &CompactF32, r: &[f32], t: &[f32], out: &mut [f32]) -> usize {
        let len = r.len();
        let end = len / 8 * 8;
        let p = s.series.p;
        let (one, two) = (_mm256_set1_ps(1.0), _mm256_set1_ps(2.0));
        let amin = _mm256_set1_ps(s.series.alpha_min as f32);
        let mut g = [_mm256_setzero_ps(); crate::ltc::compact::MAX_P];
        let mut i = 0;
        while i < end {
            let rv = unit(_mm256_loadu_ps(r.as_ptr().add(i)));
            let tv = unit(_mm256_loadu_ps(t.as_ptr().add(i)));
            let x = _mm256_sub_ps(_mm256_mul_ps(two, rv), one);
            let y = _mm256_sub_ps(_mm256_mul_ps(two, tv), one);
            let alpha = _mm256_max_ps(_mm256_mul_ps(rv, rv), amin);
            for (ch, c) in s.coeffs.iter().enumerate() {
                for (l, gl) in g.iter_mut().enumerate().take(p) {
                    *gl = clenshaw(p, |k| _mm256_set1_ps(c[p * l + k]), x);
                }
                let v = clenshaw(p, |k| g[k], y);
                let v = match s.series.channels[ch].transform {
                    Transform::Raw => v,
                    Transform::Log => super::avx2::exp(v),
                    Transform::OverAlpha => _mm256_mul_ps(v, alpha),
                };
                _mm256_storeu_ps(out.as_mut_ptr().add(ch * len + i), v);
            }
            i += 8;
        }
        end
    }

    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn lookup(tab: &TableF32, r: &[f32], t: &[f32], out: &mut [f32]) -> usize {
        let len = r.len();
        let end = len / 8 * 8;
        let n = tab.n;
        let (last, hi, one) = (
            _mm256_set1_ps((n - 1) as f32),
            _mm256_set1_ps((n - 2) as f32),
            _mm256_set1_ps(1.0),
        );
        let nv = _mm256_set1_epi32(n as i32);
        let mut i = 0;
        while i < end {
            let x = _mm256_mul_ps(unit(_mm256_loadu_ps(r.as_ptr().add(i))), last);
            let y = _mm256_mul_ps(unit(_mm256_loadu_ps(t.as_ptr().add(i))), last);
            let i0 = _mm256_min_ps(_mm256_floor_ps(x), hi);
            let j0 = _mm256_min_ps(_mm256_floor_ps(y), hi);
            let (fx, fy) = (_mm256_sub_ps(x, i0), _mm256_sub_ps(y, j0));
            let (gx, gy) = (_mm256_sub_ps(one, fx), _mm256_sub_ps(one, fy));
            let k = _mm256_add_epi32(
                _mm256_cvttps_epi32(i0),
                _mm256_mullo_epi32(nv, _mm256_cvttps_epi32(j0)),
            );
            let k1 = _mm256_add_epi32(k, _mm256_set1_epi32(1));
            let kn = _mm256_add_epi32(k, nv);
            let kn1 = _mm256_add_epi32(kn, _mm256_set1_epi32(1));
            for (ch, plane) in tab.planes.iter().enumerate() {
                let at = |idx: __m256i| _mm256_i32gather_ps::<4>(plane.as_ptr(), idx);
                let lo = _mm256_add_ps(_mm256_mul_ps(at(k), gx), _mm256_mul_ps(at(k1), fx));
                let up = _mm256_add_ps(_mm256_mul_ps(at(kn), gx), _mm256_mul_ps(at(kn1), fx));
                let v = _mm256_add_ps(_mm256_mul_ps(lo, gy), _mm256_mul_ps(up, fy));
                _mm256_storeu_ps(out.as_mut_ptr().add(ch * len + i), v);
            }
            i += 8;
        }
        end
    }
}
