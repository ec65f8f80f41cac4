//! The exact coverage of texels by a pixel: the pixel square's preimage on the map (the
//! quadrilateral of its four corners' texel coordinates — exact for a plane, where the
//! perspective map sends lines to lines, and to second order in the pixel size on curved
//! surfaces) clipped against every texel square it overlaps (Sutherland–Hodgman), giving
//! each texel's area and centroid.

/// A texel's share of a footprint: index, overlap area (texel units) and centroid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Share {
    pub i: i64,
    pub j: i64,
    pub area: f64,
    pub centroid: [f64; 2],
}

fn clip(poly: &[[f64; 2]], axis: usize, bound: f64, keep_below: bool) -> Vec<[f64; 2]> {
    let inside = |p: &[f64; 2]| {
        if keep_below {
            p[axis] <= bound
        } else {
            p[axis] >= bound
        }
    };
    let mut out = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (ia, ib) = (inside(&a), inside(&b));
        if ia {
            out.push(a);
        }
        if ia != ib {
            let t = (bound - a[axis]) / (b[axis] - a[axis]);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
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
    for j in j0..j1 {
        // the row's strip first, then each texel of it
        let row = clip(&clip(q, 1, j as f64, false), 1, (j + 1) as f64, true);
        if row.len() < 3 {
            continue;
        }
        for i in i0..i1 {
            let c = clip(&clip(&row, 0, i as f64, false), 0, (i + 1) as f64, true);
            if c.len() < 3 {
                continue;
            }
            let (a, centroid) = area_centroid(&c);
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
