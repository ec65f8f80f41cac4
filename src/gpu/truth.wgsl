// The footprint truth of the filters (seed 004 Eq 11 under Hypothesis 1): for each (v, l)
// pair, ρ_A(l, v)(n·l) = Σ_x ŵ(x) D(h)G2(l, v, h)/(4 n_x·v), every texel's isotropic GGX
// lobe around its own normal n_x (height-correlated Smith G2, F = 1), zero where v or l is
// below the geometric horizon (world z ≤ 0) or below the texel's plane. One invocation per
// pair, f32 throughout; tangential parts as |o × n|², free of the cancellation of 1 − (o·n)².

struct Params {
    texels: u32,
    pairs: u32,
    alpha: f32,
    pad: f32,
}

@group(0) @binding(0) var<storage, read> texels: array<vec4<f32>>; // n.xyz, weight
@group(0) @binding(1) var<storage, read> pairs: array<vec4<f32>>;  // v.xyz, 0, l.xyz, 0
@group(0) @binding(2) var<uniform> params: Params;
@group(0) @binding(3) var<storage, read_write> value: array<f32>;

// Λ of isotropic GGX from the cosine c and |o × n|² t2 (c > 0): a = α² t2 / c²,
// Λ = (√(1 + a) − 1)/2 = a / (2(√(1 + a) + 1)).
fn ndfb_truth_lambda(c: f32, t2: f32, a2: f32) -> f32 {
    let a = a2 * t2 / (c * c);
    return a / (2.0 * (sqrt(1.0 + a) + 1.0));
}

@compute @workgroup_size(64)
fn ndfb_truth_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if (k >= params.pairs) {
        return;
    }
    let v = pairs[2u * k].xyz;
    let l = pairs[2u * k + 1u].xyz;
    if (v.z <= 0.0 || l.z <= 0.0) {
        value[k] = 0.0;
        return;
    }
    let a2 = params.alpha * params.alpha;
    let h = normalize(v + l);
    var s = 0.0;
    for (var i = 0u; i < params.texels; i++) {
        let n = texels[i].xyz;
        let cv = dot(v, n);
        let cl = dot(l, n);
        let ch = dot(h, n);
        if (cv <= 0.0 || cl <= 0.0 || ch <= 0.0) {
            continue;
        }
        let hx = cross(h, n);
        let q = dot(hx, hx) / a2 + ch * ch;
        let d = 1.0 / (3.14159265358979 * a2 * q * q);
        let vx = cross(v, n);
        let lx = cross(l, n);
        let g2 = 1.0 / (1.0 + ndfb_truth_lambda(cv, dot(vx, vx), a2) + ndfb_truth_lambda(cl, dot(lx, lx), a2));
        s += texels[i].w * d * g2 / (4.0 * cv);
    }
    value[k] = s;
}
