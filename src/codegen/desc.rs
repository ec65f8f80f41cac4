//! The one description of every generated shading function (valid WGSL and valid Rust).
//! Cited equations: seed 003 Eq 15–18 (GGX D, Λ; anisotropic and matrix forms), seed 001
//! §1.2 (Beckmann), seed 003 Eq 10/13 (deferred kernels), seed 000 §3.3 (α_me).

/// A function body: literal text, or text unrolled by a generator (for bodies that repeat
/// one block many times, e.g. the 25 nodes of the LEADR grid).
pub enum Body {
    Text(&'static str),
    Unrolled(fn() -> String),
}

impl Body {
    pub fn text(&self) -> std::borrow::Cow<'static, str> {
        match self {
            Body::Text(t) => std::borrow::Cow::Borrowed(t),
            Body::Unrolled(f) => std::borrow::Cow::Owned(f()),
        }
    }
}

/// The 5×5 LEADR grid unrolled: node (a, b) ∈ {−2…2}² at slope offsets (a h, b h) with
/// weight W_|a|·W_|b| (seed 001 §3.4), each shaded by `leadr_env`; then the normalised sum.
fn leadr5_body() -> String {
    let mut s = String::from("    let sr: f32 = sqrt(max(1.0 - rxy * rxy, 0.0));\n");
    let mut k = 0;
    for i in -2i32..=2 {
        for j in -2i32..=2 {
            let (pi, pj) = (
                format!("{i}.0 * LEADR_SPACING_N5"),
                format!("{j}.0 * LEADR_SPACING_N5"),
            );
            let (wi, wj) = (format!("LEADR_W{}", i.abs()), format!("LEADR_W{}", j.abs()));
            s.push_str(&format!("    let nx{k}: f32 = x0 + ({pi}) * sx;\n"));
            s.push_str(&format!(
                "    let ny{k}: f32 = y0 + (({pi}) * rxy + ({pj}) * sr) * sy;\n"
            ));
            s.push_str(&format!(
                "    let i{k}: f32 = 1.0 / sqrt(nx{k} * nx{k} + ny{k} * ny{k} + 1.0);\n"
            ));
            s.push_str(&format!(
                "    let d{k}: f32 = (-nx{k} * vx - ny{k} * vy + vz) * i{k};\n"
            ));
            s.push_str(&format!(
                "    let a{k}: f32 = {wi} * {wj} * max(d{k}, 0.0) / i{k};\n"
            ));
            s.push_str(&format!(
                "    let l{k}: f32 = leadr_env(2.0 * d{k} * (-nx{k} * i{k}) - vx, 2.0 * d{k} * (-ny{k} * i{k}) - vy, 2.0 * d{k} * i{k} - vz);\n"
            ));
            k += 1;
        }
    }
    let terms: Vec<String> = (0..25).map(|q| format!("a{q} * l{q}")).collect();
    let areas: Vec<String> = (0..25).map(|q| format!("a{q}")).collect();
    s.push_str(&format!("    let num: f32 = {};\n", terms.join(" + ")));
    s.push_str(&format!("    let den: f32 = {};\n", areas.join(" + ")));
    s.push_str("    if (den <= 0.0) {\n        return 0.0;\n    }\n    return num / den;\n");
    s
}

/// One function: signature pieces and body in the neutral WGSL/Rust subset.
pub struct FnDesc {
    pub name: &'static str,
    pub doc: &'static str,
    pub params: &'static str,
    pub ret: &'static str,
    pub body: Body,
    /// Functions this one calls (must appear earlier in [`FUNCTIONS`]).
    pub deps: &'static [&'static str],
}

/// Every generated function, dependencies first.
pub const FUNCTIONS: &[FnDesc] = &[
    FnDesc {
        name: "ggx_d",
        doc: "GGX NDF, isotropic α, unit half-vector in tangent space (seed 003 Eq 15); 0 below the surface. No 1 − (n·h)² cancellation.",
        params: "hx: f32, hy: f32, hz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    if (hz <= 0.0) {
        return 0.0;
    }
    let a2: f32 = alpha * alpha;
    let s: f32 = (hx * hx + hy * hy) / a2 + hz * hz;
    return 1.0 / (PI * a2 * s * s);
"),
        deps: &[],
    },
    FnDesc {
        name: "ggx_d_aniso",
        doc: "GGX NDF, axis-aligned anisotropic (αx, αy) (seed 003 Eq 15).",
        params: "hx: f32, hy: f32, hz: f32, ax: f32, ay: f32",
        ret: "f32",
        body: Body::Text("    if (hz <= 0.0) {
        return 0.0;
    }
    let x: f32 = hx / ax;
    let y: f32 = hy / ay;
    let s: f32 = x * x + y * y + hz * hz;
    return 1.0 / (PI * ax * ay * s * s);
"),
        deps: &[],
    },
    FnDesc {
        name: "ggx_d_matrix",
        doc: "GGX NDF with an SPD roughness matrix A = [[a11, a12], [a12, a22]] (seed 003 Eq 17); adjugate form, accurate to ≈ cond(A)·ε.",
        params: "hx: f32, hy: f32, hz: f32, a11: f32, a12: f32, a22: f32",
        ret: "f32",
        body: Body::Text("    if (hz <= 0.0) {
        return 0.0;
    }
    let det: f32 = a11 * a22 - a12 * a12;
    let q: f32 = (a22 * hx * hx - 2.0 * a12 * hx * hy + a11 * hy * hy) / det;
    let s: f32 = q + hz * hz;
    return 1.0 / (PI * sqrt(det) * s * s);
"),
        deps: &[],
    },
    FnDesc {
        name: "ggx_lambda",
        doc: "GGX Smith Λ(o) = (√(1 + s²) − 1)/2, s = α|o_xy|/o_z = 1/ν (seed 003 Eq 16): s²/(2(1 + √(1 + s²))) for s ≤ 1 (no cancellation as s → 0), (√(1 + s²) − 1)/2 above, and s/2 once s > 1e18 (s² would overflow; the dropped −½ is below the last bit). Finite for every o_z > 0. Callers handle oz ≤ 0.",
        params: "ox: f32, oy: f32, oz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    let s: f32 = alpha * sqrt(ox * ox + oy * oy) / oz;
    if (s > 1e18) {
        return 0.5 * s;
    }
    let t: f32 = s * s;
    let r: f32 = sqrt(1.0 + t);
    if (t > 1.0) {
        return 0.5 * (r - 1.0);
    }
    return t / (2.0 * (1.0 + r));
"),
        deps: &[],
    },
    FnDesc {
        name: "ggx_g2",
        doc: "Height-correlated Smith G2 = 1/(1 + Λ(i) + Λ(o)) (seed 003 Eq 14); 0 when either direction is at or below the surface.",
        params: "ix: f32, iy: f32, iz: f32, ox: f32, oy: f32, oz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    if (iz <= 0.0 || oz <= 0.0) {
        return 0.0;
    }
    return 1.0 / (1.0 + ggx_lambda(ix, iy, iz, alpha) + ggx_lambda(ox, oy, oz, alpha));
"),
        deps: &["ggx_lambda"],
    },
    FnDesc {
        name: "ggx_specular",
        doc: "Point-light GGX specular times the cosine, D·G2/(4 v_z) (F = 1), tangent-space unit l and v, fused: with u = l + v, Q = √(z² + α²(x² + y²)), f = α²|u|⁴ l_z / (2π (u_x² + u_y² + α² u_z²)² (Q_l v_z + Q_v l_z)) — one division, two square roots, no normalisation (D, G2 of seed 003 Eq 14–16 combined).",
        params: "lx: f32, ly: f32, lz: f32, vx: f32, vy: f32, vz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    if (lz <= 0.0 || vz <= 0.0) {
        return 0.0;
    }
    let a2: f32 = alpha * alpha;
    let ux: f32 = lx + vx;
    let uy: f32 = ly + vy;
    let uz: f32 = lz + vz;
    let hh: f32 = ux * ux + uy * uy + uz * uz;
    let k: f32 = ux * ux + uy * uy + a2 * uz * uz;
    let ql: f32 = sqrt(lz * lz + a2 * (lx * lx + ly * ly));
    let qv: f32 = sqrt(vz * vz + a2 * (vx * vx + vy * vy));
    return a2 * hh * hh * lz / (2.0 * PI * k * k * (ql * vz + qv * lz));
"),
        deps: &[],
    },
    FnDesc {
        name: "beckmann_d",
        doc: "Beckmann NDF, isotropic α: exp(−tan²θ/α²)/(π α² cos⁴θ) (seed 001 §1.2); tan² from the components, no cancellation.",
        params: "hx: f32, hy: f32, hz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    if (hz <= 0.0) {
        return 0.0;
    }
    let c2: f32 = hz * hz;
    let t2: f32 = (hx * hx + hy * hy) / (c2 * alpha * alpha);
    return exp(-t2) / (PI * alpha * alpha * c2 * c2);
"),
        deps: &[],
    },
    FnDesc {
        name: "beckmann_lambda",
        doc: "Beckmann Smith Λ(o) by the refitted rational in ν = oz/(α√(ox² + oy²)) (results/smith-lambda.md; replaces Walter's). Callers handle oz ≤ 0.",
        params: "ox: f32, oy: f32, oz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    let sxy: f32 = alpha * sqrt(ox * ox + oy * oy);
    if (oz >= BECKMANN_LAMBDA_NU_C * sxy) {
        return 0.0;
    }
    let nu: f32 = oz / sxy;
    let c: f32 = 1.0 - nu / BECKMANN_LAMBDA_NU_C;
    let num: f32 = c * c * (1.0 + nu * (BECKMANN_LAMBDA_A1 + nu * BECKMANN_LAMBDA_A2));
    return num / (nu * (BECKMANN_LAMBDA_B1 + nu * (BECKMANN_LAMBDA_B2 + nu * BECKMANN_LAMBDA_B3)));
"),
        deps: &[],
    },
    FnDesc {
        name: "beckmann_g2",
        doc: "Height-correlated G2 for Beckmann with the refitted Λ.",
        params: "ix: f32, iy: f32, iz: f32, ox: f32, oy: f32, oz: f32, alpha: f32",
        ret: "f32",
        body: Body::Text("    if (iz <= 0.0 || oz <= 0.0) {
        return 0.0;
    }
    return 1.0 / (1.0 + beckmann_lambda(ix, iy, iz, alpha) + beckmann_lambda(ox, oy, oz, alpha));
"),
        deps: &["beckmann_lambda"],
    },
    FnDesc {
        name: "filter_sqrt_sum",
        doc: "√(α² + k), k ≥ 0, without overflow or underflow for any finite f32 α: outside α ∈ [1e-18, 1e18] it is computed as m√((α/m)² + k/m²), m = max(α, √k).",
        params: "alpha: f32, k: f32",
        ret: "f32",
        body: Body::Text("    if (alpha > 1e18 || alpha < 1e-18) {
        let sk: f32 = sqrt(k);
        let m: f32 = max(max(alpha, sk), 1.1754944e-38);
        let x: f32 = alpha / m;
        let z: f32 = sk / m;
        return m * sqrt(x * x + z * z);
    }
    return sqrt(alpha * alpha + k);
"),
        deps: &[],
    },
    FnDesc {
        name: "filter_toksvig",
        doc: "Toksvig in α²: α′² = α² + c(1 − r)/r, r = ‖μ‖ of the mip-mapped normal (seed 004 §3.2.1; c = 2 is the per-axis-variance form). r is clamped to [m, 1] (m = smallest normal f32, NaN ↦ m), so r → 0 gives a finite α′ ~ √(c/r).",
        params: "alpha: f32, r: f32, c: f32",
        ret: "f32",
        body: Body::Text("    let rc: f32 = clamp(r, 1.1754944e-38, 1.0);
    return filter_sqrt_sum(alpha, c * (1.0 - rc) / rc);
"),
        deps: &["filter_sqrt_sum"],
    },
    FnDesc {
        name: "filter_vmf",
        doc: "vMF filter α′² = α² + c/κ, κ = (3r − r³)/(1 − r²) (Banerjee), written with 1 − r; r clamped to [m, 1] as in filter_toksvig.",
        params: "alpha: f32, r: f32, c: f32",
        ret: "f32",
        body: Body::Text("    let rc: f32 = clamp(r, 1.1754944e-38, 1.0);
    let inv_kappa: f32 = (1.0 - rc) * (1.0 + rc) / (rc * (3.0 - rc * rc));
    return filter_sqrt_sum(alpha, c * inv_kappa);
"),
        deps: &["filter_sqrt_sum"],
    },
    FnDesc {
        name: "filter_vmf_fitted",
        doc: "vMF filter with the constant refitted against the footprint-averaged GGX BRDF (results/filters.md).",
        params: "alpha: f32, r: f32",
        ret: "f32",
        body: Body::Text("    return filter_vmf(alpha, r, FILTER_VMF_C_GGX);
"),
        deps: &["filter_vmf"],
    },
    FnDesc {
        name: "filter_deferred",
        doc: "Deferred isotropic kernel (seed 003 Eq 13): α′² = min(1, α² + min(2σ²(‖Δn_u‖² + ‖Δn_v‖²), δ)). Tokuyoshi σ² 0.25 δ 0.18; Filament 0.15/0.04; Unity 0.1/0.04.",
        params: "alpha: f32, dux: f32, duy: f32, duz: f32, dvx: f32, dvy: f32, dvz: f32, sigma2: f32, delta: f32",
        ret: "f32",
        body: Body::Text("    let n2: f32 = dux * dux + duy * duy + duz * duz + dvx * dvx + dvy * dvy + dvz * dvz;
    let kern: f32 = min(2.0 * sigma2 * n2, delta);
    return sqrt(min(alpha * alpha + kern, 1.0));
"),
        deps: &[],
    },
    FnDesc {
        name: "filter_deferred_fitted",
        doc: "Eq 13 with the σ² refitted for a Gaussian pixel footprint of variance 0.25 px² (the kernels' own model) and δ = 0.18 (results/filters.md).",
        params: "alpha: f32, dux: f32, duy: f32, duz: f32, dvx: f32, dvy: f32, dvz: f32",
        ret: "f32",
        body: Body::Text("    return filter_deferred(alpha, dux, duy, duz, dvx, dvy, dvz, FILTER_EQ13_SIGMA2_GAUSSIAN_PIXEL, FILTER_DELTA_MAX);
"),
        deps: &["filter_deferred"],
    },
    FnDesc {
        name: "filter_eq10",
        doc: "Exact isotropic bound (seed 003 Eq 10): α′² = α² + min(2λ_max(Σ), δ), Σ = σ²(Δ_u Δ_uᵀ + Δ_v Δ_vᵀ) of projected-disk derivatives.",
        params: "alpha: f32, dux: f32, duy: f32, dvx: f32, dvy: f32, sigma2: f32, delta: f32",
        ret: "f32",
        body: Body::Text("    let sxx: f32 = sigma2 * (dux * dux + dvx * dvx);
    let syy: f32 = sigma2 * (duy * duy + dvy * dvy);
    let sxy: f32 = sigma2 * (dux * duy + dvx * dvy);
    let h: f32 = 0.5 * (sxx - syy);
    let lmax: f32 = 0.5 * (sxx + syy) + sqrt(h * h + sxy * sxy);
    return sqrt(min(alpha * alpha + min(2.0 * lmax, delta), 1.0));
"),
        deps: &[],
    },
    FnDesc {
        name: "filter_projected",
        doc: "Projected-space kernel (Unity HDRP): p = α²/(1 − α²), p′ = p + min(2σ²Σ‖Δn‖², δ), α′² = p′/(1 + p′).",
        params: "alpha: f32, dux: f32, duy: f32, duz: f32, dvx: f32, dvy: f32, dvz: f32, sigma2: f32, delta: f32",
        ret: "f32",
        body: Body::Text("    let a2: f32 = alpha * alpha;
    if (a2 >= 1.0) {
        return 1.0;
    }
    let n2: f32 = dux * dux + duy * duy + duz * duz + dvx * dvx + dvy * dvy + dvz * dvz;
    let p: f32 = a2 / (1.0 - a2) + min(2.0 * sigma2 * n2, delta);
    return sqrt(p / (1.0 + p));
"),
        deps: &[],
    },
    FnDesc {
        name: "ltc_lut_u",
        doc: "Texture coordinate u of the LTC table for roughness α: the table is uniform in r = √α over texel centres, u = (r(n − 1) + ½)/n (bilinear filtering then reproduces the table's interpolation).",
        params: "alpha: f32",
        ret: "f32",
        body: Body::Text("    let r: f32 = sqrt(clamp(alpha, 0.0, 1.0));
    return (r * (LTC_LUT_SIZE - 1.0) + 0.5) / LTC_LUT_SIZE;
"),
        deps: &[],
    },
    FnDesc {
        name: "ltc_lut_v",
        doc: "Texture coordinate v of the LTC table for the view cosine: uniform in t = √(1 − cos θ), v = (t(n − 1) + ½)/n.",
        params: "cos_theta: f32",
        ret: "f32",
        body: Body::Text("    let t: f32 = sqrt(1.0 - clamp(cos_theta, 0.0, 1.0));
    return (t * (LTC_LUT_SIZE - 1.0) + 0.5) / LTC_LUT_SIZE;
"),
        deps: &[],
    },
    FnDesc {
        name: "ltc_edge_factor",
        doc: "θ/(2π sin θ) of a polygon edge from x = cos θ = p₁·p₂ (unit vertices): the rational fit shipped with the LTC demos (max rel. error 1.4e-6 where 1 − x² ≥ 1e-7; results/ltc-ggx.md).",
        params: "x: f32",
        ret: "f32",
        body: Body::Text("    let y: f32 = abs(x);
    let a: f32 = 0.8543985 + (0.4965155 + 0.0145206 * y) * y;
    let b: f32 = 3.417594 + (4.1616724 + y) * y;
    let v: f32 = a / b;
    if (x > 0.0) {
        return v;
    }
    return 0.5 / sqrt(max(1.0 - x * x, 0.0000001)) - v;
"),
        deps: &[],
    },
    FnDesc {
        name: "ltc_quad",
        doc: "LTC integral over a quad light (vertices p0…p3 in the shading frame: x toward the view, z the normal) with M⁻¹ ∝ [[a, 0, c], [0, 1, 0], [b, 0, d]] (the table's production form): vertices → M⁻¹p, normalised, edge vectors summed (Heitz et al. 2016), horizon by the clipped-sphere approximation max((|F|² + F_z)/(|F| + 1), 0) of the shipped shaders, clamped to ≤ 1 (a form factor; f32 edges that map to nearly antipodal directions at α → 1e-4 can otherwise push it past 1). Multiply by the table's norm. Two-sided.",
        params: "a: f32, b: f32, c: f32, d: f32, p0x: f32, p0y: f32, p0z: f32, p1x: f32, p1y: f32, p1z: f32, p2x: f32, p2y: f32, p2z: f32, p3x: f32, p3y: f32, p3z: f32",
        ret: "f32",
        body: Body::Text("    // transformed, normalised vertices
    let q0x: f32 = a * p0x + c * p0z;
    let q0z: f32 = b * p0x + d * p0z;
    let i0: f32 = 1.0 / sqrt(q0x * q0x + p0y * p0y + q0z * q0z);
    let u0x: f32 = q0x * i0;
    let u0y: f32 = p0y * i0;
    let u0z: f32 = q0z * i0;
    let q1x: f32 = a * p1x + c * p1z;
    let q1z: f32 = b * p1x + d * p1z;
    let i1: f32 = 1.0 / sqrt(q1x * q1x + p1y * p1y + q1z * q1z);
    let u1x: f32 = q1x * i1;
    let u1y: f32 = p1y * i1;
    let u1z: f32 = q1z * i1;
    let q2x: f32 = a * p2x + c * p2z;
    let q2z: f32 = b * p2x + d * p2z;
    let i2: f32 = 1.0 / sqrt(q2x * q2x + p2y * p2y + q2z * q2z);
    let u2x: f32 = q2x * i2;
    let u2y: f32 = p2y * i2;
    let u2z: f32 = q2z * i2;
    let q3x: f32 = a * p3x + c * p3z;
    let q3z: f32 = b * p3x + d * p3z;
    let i3: f32 = 1.0 / sqrt(q3x * q3x + p3y * p3y + q3z * q3z);
    let u3x: f32 = q3x * i3;
    let u3y: f32 = p3y * i3;
    let u3z: f32 = q3z * i3;
    let e0: f32 = ltc_edge_factor(u0x * u1x + u0y * u1y + u0z * u1z);
    let e1: f32 = ltc_edge_factor(u1x * u2x + u1y * u2y + u1z * u2z);
    let e2: f32 = ltc_edge_factor(u2x * u3x + u2y * u3y + u2z * u3z);
    let e3: f32 = ltc_edge_factor(u3x * u0x + u3y * u0y + u3z * u0z);
    let fx: f32 = e0 * (u0y * u1z - u0z * u1y) + e1 * (u1y * u2z - u1z * u2y) + e2 * (u2y * u3z - u2z * u3y) + e3 * (u3y * u0z - u3z * u0y);
    let fy: f32 = e0 * (u0z * u1x - u0x * u1z) + e1 * (u1z * u2x - u1x * u2z) + e2 * (u2z * u3x - u2x * u3z) + e3 * (u3z * u0x - u3x * u0z);
    let fz: f32 = e0 * (u0x * u1y - u0y * u1x) + e1 * (u1x * u2y - u1y * u2x) + e2 * (u2x * u3y - u2y * u3x) + e3 * (u3x * u0y - u3y * u0x);
    let len: f32 = sqrt(fx * fx + fy * fy + fz * fz);
    let fz2: f32 = abs(fz);
    return clamp((len * len + fz2) / (len + 1.0), 0.0, 1.0);
"),
        deps: &["ltc_edge_factor"],
    },
    FnDesc {
        name: "leadr_env",
        doc: "The analytic test environment of results/leadr-grids.md: sky 0.5 + 0.5 r_z plus a κ = 50 sun toward normalize(0.5, 0.2, 0.8) with intensity 10.",
        params: "rx: f32, ry: f32, rz: f32",
        ret: "f32",
        body: Body::Text("    let c: f32 = (0.5 * rx + 0.2 * ry + 0.8 * rz) * 1.0369517;
    return 0.5 + 0.5 * rz + 10.0 * exp(max(50.0 * (c - 1.0), -87.0));
"),
        deps: &[],
    },
    FnDesc {
        name: "leadr5_env",
        doc: "LEADR rough specular under the test environment: the 5×5 slope grid (fitted spacing h, weights φ(kh)/Σφ) of a Beckmann footprint with mean slope (x0, y0), deviations (sx, sy) and correlation rxy; each node's normal n shades L(reflect(v, n)) weighted by its projected area max(0, v·n)/n_z (seed 001 §3.4, algorithm 1). 0 when every node faces away (the §3.7 artificial micronormal is the caller's).",
        params: "x0: f32, y0: f32, sx: f32, sy: f32, rxy: f32, vx: f32, vy: f32, vz: f32",
        ret: "f32",
        body: Body::Unrolled(leadr5_body),
        deps: &["leadr_env"],
    },
    FnDesc {
        name: "alpha_me_pair",
        doc: "α_me from the pair (y, b) = (1 − ‖b̄‖, ‖b̄‖) (seed 000 §3.3), total over every f32 input: y and b are clamped to [m, 1] (m = the smallest normal f32; NaN ↦ m). y ≤ 1/3 (α ≤ 1): α = √(y/R(s)), s = −ln y, R = s/2 + (ln 2)/2 − 1 + ½ ln s + Σ c_k s^−k (exact α → 0 limit); y > 1/3: α = (π/2) g(b)/b, g = 1 + Σ d_k b^k (exact α ~ π/(2‖b̄‖) limit). Passing both keeps full relative precision at both ends. Max rel. error ≤ 1e-3 on α ∈ [1e-4, 1e2]; its measured error over the whole range: results/generated-range.md. α is the GGX/LTC roughness (Bevy: perceptual roughness²).",
        params: "y: f32, b: f32",
        ret: "f32",
        body: Body::Text("    let yc: f32 = clamp(y, 1.1754944e-38, 1.0);
    if (yc > 0.33333334) {
        let bc: f32 = clamp(b, 1.1754944e-38, 1.0);
        let g: f32 = bc * (ALPHA_ME_D1 + bc * (ALPHA_ME_D2 + bc * (ALPHA_ME_D3 + bc * (ALPHA_ME_D4 + bc * (ALPHA_ME_D5 + bc * (ALPHA_ME_D6 + bc * (ALPHA_ME_D7 + bc * ALPHA_ME_D8)))))));
        return 1.5707964 * (1.0 + g) / bc;
    }
    let s: f32 = -log(yc);
    let x: f32 = 1.0 / s;
    let p: f32 = x * (ALPHA_ME_C1 + x * (ALPHA_ME_C2 + x * (ALPHA_ME_C3 + x * (ALPHA_ME_C4 + x * (ALPHA_ME_C5 + x * (ALPHA_ME_C6 + x * ALPHA_ME_C7))))));
    let r: f32 = 0.5 * s - 0.65342640972 + 0.5 * log(s) + p;
    return sqrt(yc / r);
"),
        deps: &[],
    },
    FnDesc {
        name: "alpha_me",
        doc: "α_me from y = 1 − ‖b̄‖ alone: alpha_me_pair(y, 1 − y) (1 − y is exact for y ≥ ½). Pass the pair where ‖b̄‖ itself is known and tiny.",
        params: "y: f32",
        ret: "f32",
        body: Body::Text("    return alpha_me_pair(y, 1.0 - y);
"),
        deps: &["alpha_me_pair"],
    },
    FnDesc {
        name: "multiscale_alpha",
        doc: "Overall α of the multi-scale lobe by the product identity ρ = ρ_me·ρ_mi (proofs/mrl-product.md), from y_me = 1 − ‖μ‖ of the mip and the per-material y_mi = 1 − ρ(α_mi): 1 − ρ = y_me + y_mi − y_me·y_mi and ρ = (1 − y_me)(1 − y_mi), each without cancellation (pass the y's, not ‖μ‖ and ρ: in f32 1 − ‖μ‖ρ loses ε/y relative).",
        params: "y_me: f32, y_mi: f32",
        ret: "f32",
        body: Body::Text("    return alpha_me_pair(y_me + y_mi - y_me * y_mi, (1.0 - y_me) * (1.0 - y_mi));
"),
        deps: &["alpha_me_pair"],
    },
];

/// What each parameter name means, in the engines' conventions: the sentence each
/// generated function's doc comment carries for the parameters it takes.
pub const CONVENTIONS: &[(&[&str], &str)] = &[
    (
        &["alpha", "ax", "ay"],
        "GGX/Beckmann α, the squared perceptual roughness: Bevy's `roughness = perceptualRoughnessToRoughness(perceptual_roughness)` (pbr_functions), glTF's α = roughnessFactor², three.js's `roughness * roughness`",
    ),
    (
        &["a11", "a12", "a22"],
        "the SPD roughness matrix in α units (diag(αx, αy) rotated into the tangent frame)",
    ),
    (
        &["hx", "hy", "hz", "lx", "ly", "lz", "vx", "vy", "vz", "ox", "oy", "oz", "ix", "iy", "iz"],
        "unit directions in tangent space, z along the shading normal (Bevy: the world-space vectors times the transposed TBN)",
    ),
    (
        &["r"],
        "r = ‖μ‖, the length of the mip-filtered normal before renormalisation (sample a normal map whose mips were not renormalised)",
    ),
    (
        &["dux", "duy", "duz", "dvx", "dvy", "dvz"],
        "screen-space derivatives of the shading normal: dpdx(N) and dpdy(N) in a fragment shader",
    ),
    (
        &["cos_theta"],
        "cos θ_v = clamp(dot(N, V), 0, 1)",
    ),
    (
        &["y", "y_me", "y_mi", "b"],
        "y = 1 − ‖b̄‖ and b = ‖b̄‖, the mean-vector length of a lobe or of a mip's normals (pass y, not ‖b̄‖, when it is small)",
    ),
];

/// The "Inputs:" sentence of a function's doc comment (empty when no parameter has a
/// stated convention).
pub fn inputs_doc(params: &str) -> String {
    let names: Vec<&str> = params
        .split(',')
        .filter_map(|p| p.split(':').next())
        .map(str::trim)
        .collect();
    let parts: Vec<String> = CONVENTIONS
        .iter()
        .filter_map(|(keys, what)| {
            let used: Vec<&str> = keys.iter().copied().filter(|k| names.contains(k)).collect();
            (!used.is_empty()).then(|| format!("{}: {what}", used.join(", ")))
        })
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!("Inputs — {}.", parts.join("; "))
    }
}
