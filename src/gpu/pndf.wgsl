// P-NDF images by brute force (seed 002 Eq 2), one invocation per (footprint, bin):
// D(h) = Σ_u G_P(u; x, σ_P) · G_r(n(u)_xy; h_xy, σ_r) / Σ_u G_P(u; x, σ_P), the texels
// within 4σ_P of the footprint's centre (periodic map), both cut-offs as the f64
// reference's (G_P < 1e-12 dropped, exponent ≥ 40 dropped). f32 throughout.

struct Params {
    width: u32,
    height: u32,
    res: u32,
    rad: i32,
    footprints: u32,
    sigma_p: f32,
    sigma_r: f32,
    first: u32,
}

@group(0) @binding(0) var<storage, read> normals: array<vec2<f32>>;
@group(0) @binding(1) var<storage, read> centres: array<vec2<f32>>;
@group(0) @binding(2) var<uniform> params: Params;
@group(0) @binding(3) var<storage, read_write> image: array<f32>;

@compute @workgroup_size(64)
fn ndfb_pndf_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let bins = params.res * params.res;
    let k = id.x;
    if (k >= bins * params.footprints) {
        return;
    }
    let f = params.first + k / bins;
    let b = k % bins;
    let cell = 2.0 / f32(params.res);
    let h = vec2<f32>(-1.0 + (f32(b % params.res) + 0.5) * cell, -1.0 + (f32(b / params.res) + 0.5) * cell);
    let c = centres[f];
    let base = vec2<i32>(floor(c));
    let inv_p = 1.0 / (2.0 * params.sigma_p * params.sigma_p);
    let inv_r = 1.0 / (2.0 * params.sigma_r * params.sigma_r);
    let w = i32(params.width);
    let ht = i32(params.height);
    var s = 0.0;
    var wsum = 0.0;
    for (var dy = -params.rad; dy <= params.rad; dy++) {
        for (var dx = -params.rad; dx <= params.rad; dx++) {
            let p = base + vec2<i32>(dx, dy);
            let u = vec2<f32>(p) + vec2<f32>(0.5) - c;
            let g = exp(-dot(u, u) * inv_p);
            if (g < 1e-12) {
                continue;
            }
            let q = vec2<i32>(((p.x % w) + w) % w, ((p.y % ht) + ht) % ht);
            let n = normals[q.y * w + q.x];
            wsum += g;
            let d = n - h;
            let e = dot(d, d) * inv_r;
            if (e < 40.0) {
                s += g * exp(-e);
            }
        }
    }
    image[k] = s * inv_r / (3.14159265358979 * wsum);
}
