//! The footprint roughness filters, written once over `num_traits::Float`:
//! `T = f64` is the reference, `T = f32` the shading form (tests/filters.rs bounds the
//! difference; see each function for its conditioning).
//!
//! Map filters read mip-mapped statistics ([`super::footprint::Stats`]); screen-space
//! kernels read derivatives of normals or half-vectors across a 2×2 pixel quad.
//! Roughness convention: GGX/Beckmann α, roughness matrix A = 2·(slope covariance) for
//! Beckmann (seed 003 Eq 3), used as is for GGX (seed 003 §2).
//!
//! In seed 004 §7's terms ([`crate::survey::tools`]): Toksvig and the vMF rules are
//! convolution methods with the moments tool (one moment of the macroscopic NDF, the mean
//! normal, the second deduced from it); LEAN is a direct moments method (Eq 19).
//!
//! [`MapRule`] and [`ScreenRule`] name one rule with its constants, as the registry of
//! filters ([`super::registry`]) lists them, and evaluate it at either precision.

use num_traits::Float;

#[inline]
fn k<T: Float>(x: f64) -> T {
    // NumCast f64 → f32/f64 is total for finite constants.
    T::from(x).unwrap_or_else(T::nan)
}

/// The mean-normal length clamped to [m, 1] (m the smallest normal number; NaN ↦ m): a
/// mip of opposed normals has r → 0, and the filters below stay finite there (their α′
/// grows like r^(−1/2), the exact limit) instead of dividing by zero.
#[inline]
pub fn clamp_r<T: Float>(r: T) -> T {
    r.max(T::min_positive_value()).min(T::one())
}

/// √(α² + k) without overflow for any finite α and k ≥ 0 (the filters' last step).
#[inline]
pub fn sqrt_sum<T: Float>(alpha: T, k: T) -> T {
    alpha.hypot(k.max(T::zero()).sqrt())
}

/// Toksvig's variance from the mean-normal length r = |μ| (seed 004 §3.2.1):
/// σ² = (1 − r)/r, r clamped by [`clamp_r`].
pub fn toksvig_sigma2<T: Float>(r: T) -> T {
    let r = clamp_r(r);
    (T::one() - r) / r
}

/// Toksvig, Blinn–Phong form (seed 004 §3.2.1, the equation after Eq 19): the exponent
/// s = 2/α² − 2 becomes s′ = s/(1 + sσ²), then α′ = √(2/(s′ + 2)). For α ≥ 1 (s ≤ 0)
/// the Blinn–Phong lobe does not exist; α is returned unchanged.
///
/// Written without s itself, which overflows as α → 0: with u = 1/s = α²/(2(1 − α²)) and
/// v = u + σ², s′ = 1/v and α′² = 2v/(1 + 2v) (σ² = 0 gives α′ = α exactly). Where v
/// underflows (α and σ² both below ~1e-154 in f64) α is returned.
pub fn toksvig_bp<T: Float>(alpha: T, r: T) -> T {
    let one = T::one();
    let two = k::<T>(2.0);
    let a2 = alpha * alpha;
    if !(a2 < one) {
        return alpha;
    }
    let v = a2 / (two * (one - a2)) + toksvig_sigma2(r);
    if !(v > T::zero()) {
        return alpha;
    }
    (two * v / (one + two * v)).sqrt()
}

/// Toksvig in α²: α′² = α² + c·σ². c = 2 follows from σ² being a per-axis variance and
/// the Beckmann slope variance being α²/2; c = 1 is the variant some engines ship.
pub fn toksvig_alpha2<T: Float>(alpha: T, r: T, c: T) -> T {
    sqrt_sum(alpha, c * toksvig_sigma2(r))
}

/// 1/κ of Banerjee et al.'s κ ≈ (3r − r³)/(1 − r²), written (1 − r)(1 + r)/(r(3 − r²))
/// so that r → 1 gives 0 without cancellation; r clamped as in [`clamp_r`].
pub fn inv_kappa<T: Float>(r: T) -> T {
    let one = T::one();
    let r = clamp_r(r);
    (one - r) * (one + r) / (r * (k::<T>(3.0) - r * r))
}

/// vMF filter (Banerjee et al.'s κ ≈ (3r − r³)/(1 − r²)): α′² = α² + c/κ,
/// c/κ = c(1 − r)(1 + r)/(r(3 − r²)) — written with 1 − r so that r → 1 gives 0 without
/// cancellation (an f32 r carries relative error ε, so c/κ's relative error is
/// ≈ ε/(1 − r): the input, not this form, limits it).
pub fn vmf<T: Float>(alpha: T, r: T, c: T) -> T {
    let inv_kappa = inv_kappa(r);
    sqrt_sum(alpha, c * inv_kappa)
}

/// LEAN (seed 004 Eq 19; Olano–Baker): the slope covariance Σ = E[x̃x̃ᵀ] − E[x̃]E[x̃]ᵀ of
/// the footprint plus the base roughness: A = α²I + 2Σ, mean slope E[x̃]. Returns
/// (A_xx, A_yy, A_xy); the mean slope is passed through by the caller.
pub fn lean<T: Float>(alpha: T, cov: [T; 3]) -> [T; 3] {
    let two = k::<T>(2.0);
    let a2 = alpha * alpha;
    [a2 + two * cov[0], a2 + two * cov[1], two * cov[2]]
}

/// Filament's roughness-prefilter tool (tools/roughness-prefilter, after Karis 2018):
/// p′ = √(p² + 2/κ) on the perceptual roughness p = √α, i.e. α′ = α + 2/κ — the vMF term
/// added to α rather than to α². Same κ as [`vmf`].
pub fn filament_prefilter<T: Float>(alpha: T, r: T) -> T {
    let inv_kappa = inv_kappa(r);
    alpha + k::<T>(2.0) * inv_kappa
}

/// Godot's import-time roughness limiter (core/io/image.cpp, `generate_mipmap_roughness`):
/// variance = 0.25/κ, p′ = √(p² + min(3·variance, 0.4²)) on the perceptual roughness,
/// i.e. α′ = α + min(0.75/κ, 0.16).
pub fn godot_limiter<T: Float>(alpha: T, r: T) -> T {
    let inv_kappa = inv_kappa(r);
    alpha + (k::<T>(0.75) * inv_kappa).min(k::<T>(0.16))
}

/// Seed 000 Eq 5 (α_me from ‖b̄‖ = |μ|), clamped at 0 (it is negative for
/// ‖b̄‖ > 0.999725, results/multiscale-alpha-me.md), combined with the base α by Eq 7.
pub fn seed000_paper<T: Float>(alpha: T, r: T) -> T {
    let b = r;
    let num = (((k::<T>(1.629) * b + k(17.05)) * b - k(18.96)) * b - k(23.37)) * b + k(23.65);
    let den = ((b - k(28.07)) * b + k(31.1)) * b - k(3.545);
    let ame = (num / den).max(T::zero());
    k::<T>(0.07) * alpha * alpha + k::<T>(0.94) * alpha + ame - k::<T>(0.83) * alpha * ame
}

/// Our seed-000 form of the mean-normal filter: under the moment metric the overall
/// lobe has ρ = |μ|·ρ(α) (proofs/mrl-product.md), so α′ = ρ⁻¹(|μ|ρ(α)). `rho_base` = ρ(α)
/// is a per-material constant; ρ⁻¹ is the `Ours` fit of results/fits/multiscale-alpha-me
/// (both branches, `small` and `large`, evaluated at y = 1 − |μ|ρ(α); total over every
/// input: see [`crate::multiscale::alpha_me::ours_eval_t`]).
pub fn seed000_moment_fit<T: Float>(r: T, rho_base: T, small: &[T], large: &[T]) -> T {
    let b = r * rho_base;
    crate::multiscale::alpha_me::ours_eval_pair_t(small, large, T::one() - b, b)
}

/// ‖dn_u‖² + ‖dn_v‖² of two 3-vectors.
fn sum_sq<T: Float>(du: [T; 3], dv: [T; 3]) -> T {
    du[0] * du[0] + du[1] * du[1] + du[2] * du[2] + dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]
}

/// Deferred isotropic kernel (seed 003 Eq 13, Listing 2) with screen variance σ² and
/// clamp δ: α′² = α² + min(2σ²(‖Δn_u‖² + ‖Δn_v‖²), δ), saturated to ≤ 1.
/// Tokuyoshi: σ² = 0.25, δ = 0.18. Filament: σ² = 0.15, δ = 0.04. Unity HDRP: σ² = 0.1,
/// δ = 0.04. δ = +∞ is the unclamped kernel.
pub fn deferred<T: Float>(alpha: T, du: [T; 3], dv: [T; 3], sigma2: T, delta: T) -> T {
    let kern = (k::<T>(2.0) * sigma2 * sum_sq(du, dv)).min(delta);
    (alpha * alpha + kern).min(T::one()).sqrt()
}

/// The same kernel added to α instead of α² (Godot 4: its "roughness" is perceptual,
/// so roughness² = α): α′ = min(1, α + min(2σ²(‖Δn_u‖² + ‖Δn_v‖²), δ)).
pub fn deferred_on_alpha<T: Float>(alpha: T, du: [T; 3], dv: [T; 3], sigma2: T, delta: T) -> T {
    let kern = (k::<T>(2.0) * sigma2 * sum_sq(du, dv)).min(delta);
    (alpha + kern).min(T::one())
}

/// Projected-space variant (Unity HDRP): p = α²/(1 − α²), p′ = p + min(2σ²Σ‖Δn‖², δ),
/// α′² = p′/(1 + p′). α ≥ 1 is returned as 1.
pub fn projected_space<T: Float>(alpha: T, du: [T; 3], dv: [T; 3], sigma2: T, delta: T) -> T {
    let a2 = alpha * alpha;
    if !(a2 < T::one()) {
        return T::one();
    }
    let p = a2 / (T::one() - a2);
    let pp = p + (k::<T>(2.0) * sigma2 * sum_sq(du, dv)).min(delta);
    (pp / (T::one() + pp)).sqrt()
}

/// Largest eigenvalue of the symmetric 2×2 [[a, c], [c, b]], without cancellation:
/// (a + b)/2 + √(((a − b)/2)² + c²).
fn lambda_max<T: Float>(a: T, b: T, c: T) -> T {
    let h = k::<T>(0.5);
    (a + b) * h + ((a - b) * h).hypot(c)
}

/// Σ = σ²(Δ_u Δ_uᵀ + Δ_v Δ_vᵀ) as (xx, yy, xy) (seed 003 Eq 2 / Eq 7).
pub fn kernel_cov<T: Float>(du: [T; 2], dv: [T; 2], sigma2: T) -> [T; 3] {
    [
        sigma2 * (du[0] * du[0] + dv[0] * dv[0]),
        sigma2 * (du[1] * du[1] + dv[1] * dv[1]),
        sigma2 * (du[0] * du[1] + dv[0] * dv[1]),
    ]
}

/// Exact isotropic bound (seed 003 Eq 10): α′² = α² + min(2λ_max(Σ), δ), Σ from the
/// projected-disk derivatives of the normal.
pub fn eigen_eq10<T: Float>(alpha: T, du: [T; 2], dv: [T; 2], sigma2: T, delta: T) -> T {
    let s = kernel_cov(du, dv, sigma2);
    let kern = (k::<T>(2.0) * lambda_max(s[0], s[1], s[2])).min(delta);
    (alpha * alpha + kern).min(T::one()).sqrt()
}

/// Kaplanyan et al. 2016 rectangular kernel (seed 003 Listing 3): bounding rectangle
/// |Δ_u| + |Δ_v| of the slope-space derivatives of the (quad-frame) normal, its larger
/// side w, variance σ²w², α′² = α² + min(2σ²w², δ), saturated.
pub fn kaplanyan_rect<T: Float>(alpha: T, du: [T; 2], dv: [T; 2], sigma2: T, delta: T) -> T {
    let bx = du[0].abs() + dv[0].abs();
    let by = du[1].abs() + dv[1].abs();
    let w = bx.max(by);
    let kern = (k::<T>(2.0) * sigma2 * w * w).min(delta);
    (alpha * alpha + kern).min(T::one()).sqrt()
}

/// Forward anisotropic kernel: A = α²I + 2Σ (seed 003 Eq 3) with Σ from half-vector
/// derivatives — in slope space (Kaplanyan, Eq 2) or on the projected disk (Tokuyoshi,
/// Eq 7); the caller supplies the derivatives of the chosen space. Returns (xx, yy, xy).
pub fn forward_matrix<T: Float>(alpha: T, du: [T; 2], dv: [T; 2], sigma2: T) -> [T; 3] {
    let s = kernel_cov(du, dv, sigma2);
    let two = k::<T>(2.0);
    let a2 = alpha * alpha;
    [a2 + two * s[0], a2 + two * s[1], two * s[2]]
}

/// How a map filter turns the base α and the mip's mean-normal length r into α′.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapRule {
    /// the renormalised mip normal with the base α
    Renormalised,
    /// Toksvig, Blinn–Phong form
    ToksvigBp,
    /// Toksvig α² + c·σ²
    Toksvig(f64),
    /// vMF α² + c/κ
    Vmf(f64),
    /// LEAN's anisotropic matrix A = α²I + 2Σ with the mean slope (no isotropic α′)
    Lean,
    /// seed 000 Eq 5 + Eq 7 as printed
    Seed000Paper,
    /// the product identity ρ⁻¹(‖μ‖ρ(α)) (seed 000's moment)
    Moment,
    /// Filament's roughness-prefilter
    Filament,
    /// Godot's roughness limiter
    Godot,
}

impl MapRule {
    /// α′ of the isotropic rules at base α and mean-normal length r, in T (f64: the
    /// reference; f32: the shading form). The moment rule takes ρ⁻¹(‖μ‖ρ(α)) from
    /// `moment` (Newton in f64, the fitted form in f32); LEAN is anisotropic: `None`.
    pub fn alpha<T: Float>(self, alpha: T, r: T, moment: impl FnOnce() -> T) -> Option<T> {
        Some(match self {
            MapRule::Renormalised => alpha,
            MapRule::ToksvigBp => toksvig_bp(alpha, r),
            MapRule::Toksvig(c) => toksvig_alpha2(alpha, r, k(c)),
            MapRule::Vmf(c) => vmf(alpha, r, k(c)),
            MapRule::Lean => return None,
            MapRule::Seed000Paper => seed000_paper(alpha, r),
            MapRule::Moment => moment(),
            MapRule::Filament => filament_prefilter(alpha, r),
            MapRule::Godot => godot_limiter(alpha, r),
        })
    }

    /// Whether the rule works on perceptual roughness p = √α as the engines' import tools
    /// do (a texture tool then averages p, not α²).
    pub fn on_perceptual(self) -> bool {
        matches!(self, MapRule::Filament | MapRule::Godot)
    }

    /// The same rule with its constant replaced by a refitted one (rules without a
    /// constant are returned as they are).
    pub(crate) fn with_constant(self, c: f64) -> MapRule {
        match self {
            MapRule::Toksvig(_) => MapRule::Toksvig(c),
            MapRule::Vmf(_) => MapRule::Vmf(c),
            r => r,
        }
    }
}

/// How a screen-space kernel turns the base α and the pixel quad's derivatives into α′
/// (σ² the kernel variance, δ the clamp; ∞ for none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ScreenRule {
    /// no antialiasing: the base α
    None,
    /// Tokuyoshi's deferred kernel on α² (seed 003 Eq 13; Filament's and Unity's form)
    Deferred { s2: f64, delta: f64 },
    /// the same kernel added to α (Godot)
    DeferredOnAlpha { s2: f64, delta: f64 },
    /// the exact largest eigenvalue (seed 003 Eq 10) of the projected-disk derivatives
    Eigen { s2: f64, delta: f64 },
    /// Kaplanyan's rect (Listing 3, as intended: in the quad average's frame)
    KaplanyanRect { s2: f64, delta: f64 },
    /// Unity's projected-space form
    ProjectedSpace { s2: f64, delta: f64 },
    /// a forward kernel per light: slope space (Kaplanyan, Eq 2–3) or the projected disk
    /// (Tokuyoshi, Eq 7); anisotropic, so no isotropic α′
    Forward { slope: bool },
}

impl ScreenRule {
    /// α′ of the kernels that read the derivatives of the world normal across the quad
    /// (3-vectors: the deferred kernels and the projected-space form), in T (f64: the
    /// reference; f32: the shading form); `None` for the other kernels.
    pub fn alpha_from_normals<T: Float>(self, alpha: T, du: [T; 3], dv: [T; 3]) -> Option<T> {
        Some(match self {
            ScreenRule::None => alpha,
            ScreenRule::Deferred { s2, delta } => deferred(alpha, du, dv, k(s2), k(delta)),
            ScreenRule::DeferredOnAlpha { s2, delta } => {
                deferred_on_alpha(alpha, du, dv, k(s2), k(delta))
            }
            ScreenRule::ProjectedSpace { s2, delta } => {
                projected_space(alpha, du, dv, k(s2), k(delta))
            }
            _ => return None,
        })
    }

    /// α′ of the kernels that read 2D derivatives: Eq 10 (projected-disk derivatives of
    /// the normal) and Kaplanyan's rect (slope-space derivatives in the quad average's
    /// frame); `None` for the other kernels.
    pub fn alpha_from_2d<T: Float>(self, alpha: T, du: [T; 2], dv: [T; 2]) -> Option<T> {
        Some(match self {
            ScreenRule::Eigen { s2, delta } => eigen_eq10(alpha, du, dv, k(s2), k(delta)),
            ScreenRule::KaplanyanRect { s2, delta } => {
                kaplanyan_rect(alpha, du, dv, k(s2), k(delta))
            }
            _ => return None,
        })
    }

    /// The same kernel with its variance σ² replaced by a refitted one.
    pub(crate) fn with_constant(self, c: f64) -> ScreenRule {
        match self {
            ScreenRule::Deferred { delta, .. } => ScreenRule::Deferred { s2: c, delta },
            ScreenRule::DeferredOnAlpha { delta, .. } => {
                ScreenRule::DeferredOnAlpha { s2: c, delta }
            }
            ScreenRule::Eigen { delta, .. } => ScreenRule::Eigen { s2: c, delta },
            ScreenRule::KaplanyanRect { delta, .. } => ScreenRule::KaplanyanRect { s2: c, delta },
            ScreenRule::ProjectedSpace { delta, .. } => ScreenRule::ProjectedSpace { s2: c, delta },
            r => r,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambda_max_matches_definition() {
        // [[2, 1], [1, 2]] has eigenvalues 1 and 3
        assert!((lambda_max(2.0, 2.0, 1.0) - 3.0f64).abs() < 1e-15);
    }
}
