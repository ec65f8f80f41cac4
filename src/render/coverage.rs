//! The exact coverage of texels by a pixel: the pixel square's preimage on the map (the
//! quadrilateral of its four corners' texel coordinates — exact for a plane, where the
//! perspective map sends lines to lines, and to second order in the pixel size on curved
//! surfaces) clipped against every texel square it overlaps (Sutherland–Hodgman), giving
//! each texel's area and centroid.

/// Footprints of at most this many texels (bounding box) are integrated texel by texel by
/// the truth (render::truth); larger ones are supersampled.
pub const MAX_EXACT_TEXELS: usize = 4096;

/// A texel's share of a footprint: index, overlap area (texel units) and centroid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Share {
    pub i: i64,
    pub j: i64,
    pub area: f64,
    pub centroid: [f64; 2],
}

/// A polygon of at most [`Poly::CAP`] vertices, kept on the stack: the clips of one
/// footprint run once per texel it overlaps, and a heap vector per clip cost more than the
/// clipping itself.
#[derive(Clone, Copy)]
struct Poly {
    n: usize,
    p: [[f64; 2]; Poly::CAP],
}

impl Poly {
    /// Clipping a polygon of k vertices against a half-plane keeps its inside vertices and
    /// adds one per crossing, and between two crossings at least one vertex is outside, so
    /// at most 3k/2 remain: the quadrilateral's 4 become at most 6, 9, 13, 19 over the four
    /// clips of a texel, convex or not.
    const CAP: usize = 24;

    fn quad(q: &[[f64; 2]; 4]) -> Poly {
        let mut p = [[0.0; 2]; Poly::CAP];
        p[..4].copy_from_slice(q);
        Poly { n: 4, p }
    }

    fn points(&self) -> &[[f64; 2]] {
        &self.p[..self.n]
    }
}

/// `poly` clipped to one side of the line x_axis = bound (Sutherland–Hodgman).
#[cfg(test)]
fn clip(poly: &Poly, axis: usize, bound: f64, keep_below: bool) -> Poly {
    let mut out = Poly::quad(&[[0.0; 2]; 4]);
    clip_into(poly, axis, bound, keep_below, &mut out);
    out
}

/// [`clip`] written into `out` (its vertices overwritten): the clips of a footprint run
/// four per texel, and a polygon returned by value is copied, and first zeroed, each time.
fn clip_into(poly: &Poly, axis: usize, bound: f64, keep_below: bool, out: &mut Poly) {
    let inside = |p: &[f64; 2]| {
        if keep_below {
            p[axis] <= bound
        } else {
            p[axis] >= bound
        }
    };
    out.n = 0;
    let mut push = |v: [f64; 2]| {
        out.p[out.n] = v;
        out.n += 1;
    };
    let pts = poly.points();
    for k in 0..pts.len() {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        let (ia, ib) = (inside(&a), inside(&b));
        if ia {
            push(a);
        }
        if ia != ib {
            let t = (bound - a[axis]) / (b[axis] - a[axis]);
            push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
}

/// Signed area and centroid of a polygon (shoelace).
pub fn area_centroid(p: &[[f64; 2]]) -> (f64, [f64; 2]) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..p.len() {
        let (u, v) = (p[k], p[(k + 1) % p.len()]);
        let c = u[0] * v[1] - v[0] * u[1];
        a += c;
        cx += (u[0] + v[0]) * c;
        cy += (u[1] + v[1]) * c;
    }
    let a = 0.5 * a;
    if a.abs() < 1e-300 {
        return (0.0, p.first().copied().unwrap_or([0.0; 2]));
    }
    (a, [cx / (6.0 * a), cy / (6.0 * a)])
}

/// Every texel the convex quadrilateral `q` overlaps, with its share; `None` when the
/// bounding box holds more than `max` texels (the caller samples instead).
pub fn shares(q: &[[f64; 2]; 4], max: usize) -> Option<Vec<Share>> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in q {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        for a in 0..2 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let (i0, i1) = (lo[0].floor() as i64, hi[0].ceil() as i64);
    let (j0, j1) = (lo[1].floor() as i64, hi[1].ceil() as i64);
    let count = ((i1 - i0) as f64) * ((j1 - j0) as f64);
    if !(count <= max as f64) {
        return None;
    }
    let mut out = Vec::new();
    let quad = Poly::quad(q);
    // the clips' polygons, reused: the row's strip, then each texel of it
    let (mut half, mut row, mut cell) = (quad, quad, quad);
    for j in j0..j1 {
        clip_into(&quad, 1, j as f64, false, &mut half);
        clip_into(&half, 1, (j + 1) as f64, true, &mut row);
        if row.n < 3 {
            continue;
        }
        for i in i0..i1 {
            clip_into(&row, 0, i as f64, false, &mut half);
            clip_into(&half, 0, (i + 1) as f64, true, &mut cell);
            let c = &cell;
            if c.n < 3 {
                continue;
            }
            let (a, centroid) = area_centroid(c.points());
            if a.abs() > 0.0 {
                out.push(Share {
                    i,
                    j,
                    area: a.abs(),
                    centroid,
                });
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Any four corners, convex, concave or crossed, stay within the clip's fixed capacity
    /// (each clip keeps at most 3k/2 of k vertices, the bound `Poly::CAP` rests on), and a
    /// simple (uncrossed) quadrilateral's shares add up to its area: 20 000 random
    /// quadrilaterals over a few texels, half of them with a corner pulled inside.
    #[test]
    fn any_quadrilateral_clips_within_capacity() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut simple = 0;
        for k in 0..20_000 {
            let mut q = [[0.0; 2]; 4];
            for p in &mut q {
                *p = [rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0)];
            }
            if k % 2 == 0 {
                // a dart: the third corner between the centroid of the others and the first
                let c = [
                    (q[0][0] + q[1][0] + q[3][0]) / 3.0,
                    (q[0][1] + q[1][1] + q[3][1]) / 3.0,
                ];
                let t: f64 = rng.random();
                q[2] = [c[0] + t * (q[0][0] - c[0]), c[1] + t * (q[0][1] - c[1])];
            }
            // the capacity's argument, clip by clip: k vertices become at most 3k/2
            let mut p = Poly::quad(&q);
            for (axis, below) in [(1, false), (1, true), (0, false), (0, true)] {
                let c = clip(&p, axis, rng.random_range(-3.0..3.0), below);
                assert!(2 * c.n <= 3 * p.n, "{q:?}: {} vertices from {}", c.n, p.n);
                p = c;
            }
            let sh = shares(&q, 1 << 10).expect("bounded and finite");
            let crossed = {
                let cross = |a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]| {
                    let o = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
                        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
                    };
                    o(a, b, c) * o(a, b, d) < 0.0 && o(c, d, a) * o(c, d, b) < 0.0
                };
                cross(q[0], q[1], q[2], q[3]) || cross(q[1], q[2], q[3], q[0])
            };
            if !crossed {
                simple += 1;
                let total: f64 = sh.iter().map(|s| s.area).sum();
                let area = area_centroid(&q).0.abs();
                assert!(
                    (total - area).abs() <= 1e-9 * area.max(1.0),
                    "{q:?}: {total} vs {area}"
                );
            }
        }
        assert!(simple > 5_000, "{simple} simple quadrilaterals");
    }
}
