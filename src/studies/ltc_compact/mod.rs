//! `regen --only ltc-compact` (on request): LTC tables as a few hundred coefficients
//! (`ltc::compact`: a tensor-product Chebyshev series per channel), judged the way a shader
//! uses them.
//!
//! For the GGX table and both sheen tables (Estevez–Kulla's Λ, glTF's; Neubelt's
//! visibility, three.js's and Filament's) as published, each
//! transform set and each degree p of the spec gives a compact form (6·p² coefficients).
//! Each form is judged at every `every`-th cell (texel centre) and square centre along
//! each axis, against the true lobe at that place, by the exact held-out figures of
//! `ltc::lobe_error` (converged integrals with their bars), in two ways:
//!
//! - **rebuilt:** the series evaluated at the texel centres, stored as the nearest
//!   binary16 and read bilinearly (at a square centre: the mean of its four corners), as
//!   an engine that rebuilds its textures at start-up would sample them;
//! - **texture-free:** the series evaluated in f32 at the place itself, as a shader with
//!   no texture would.
//!
//! All forms at a place, and the full table's stored binary16 entries, are judged in one
//! cubature (the lobe evaluated once per node for all of them). For GGX the shipped
//! table's figures at the same places come from results/ltc-compare.json (each engine
//! path's reachable places), and every place counts as better, tied or worse beyond both
//! bars. It reads the published tables and does not rerun their studies (its cache is
//! keyed by each table's fingerprint). The goal (for GGX): at most `max_coefficients`, no reachable place worse than the
//! shipped table, and a mean within `within_points` of the full table's. Writes
//! results/ltc-compact.{md,svg} and results/fits/ltc-compact.json.

use crate::error::{Error, Result};
use crate::ltc::compact::{Compact, Transform};
use crate::ltc::compact_fit::{refine, LobeFit, Trace};
use crate::ltc::compare::{cell_error_of, square_entries, stored_half, Shipped};
use crate::ltc::lobe_error::{LobeError, Spread, Tolerance};
use crate::ltc::lobes::Lobe;
use crate::ltc::target::{GgxTarget, LtcTarget};
use crate::results::ltc_compact::{CompactFamily, CompactForm, Judged, ShippedPath, TextureFree};
use crate::study::{Ctx, FitOutcome};

mod polygons;
pub mod report;

/// What fits/ltc-compact.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Series degrees p (coefficients per channel p²), strictly increasing.
    pub degrees: Vec<usize>,
    /// Judge every `every`-th cell and square along each axis.
    pub every: usize,
    /// The held-out figures' relative tolerance.
    pub held_out_rel: f64,
    /// The goal: at most this many coefficients …
    pub max_coefficients: usize,
    /// … and a mean relative L2 within this many points of the full table's.
    pub within_points: f64,
    /// Degrees whose form (of each table's lobe-fit transform set) is then refined by the
    /// lobe error after bilinear reading (`ltc::compact_fit`), each judged as a form of its own.
    pub lobe_degrees: Vec<usize>,
    /// The lobe fit: 3·n² nodes per training place, iterations per pass, passes.
    pub lobe_nodes: usize,
    pub lobe_iterations: usize,
    pub lobe_passes: usize,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        crate::fit::spec::within("every", self.every, 1, 64)?;
        crate::fit::spec::within("degrees (its length)", self.degrees.len(), 1, 16)?;
        for &p in &self.degrees {
            crate::fit::spec::within("degrees", p, 1, crate::ltc::compact::MAX_P)?;
        }
        if !self.degrees.windows(2).all(|w| w[0] < w[1]) {
            return Err(format!(
                "degrees = {:?} must increase strictly",
                self.degrees
            ));
        }
        crate::fit::spec::within("lobe_degrees (its length)", self.lobe_degrees.len(), 0, 8)?;
        for &p in &self.lobe_degrees {
            crate::fit::spec::within("lobe_degrees", p, 1, 24)?;
        }
        crate::fit::spec::within("lobe_nodes", self.lobe_nodes, 2, 64)?;
        crate::fit::spec::within("lobe_iterations", self.lobe_iterations, 1, 200)?;
        crate::fit::spec::within("lobe_passes", self.lobe_passes, 1, 8)?;
        crate::fit::spec::within("max_coefficients", self.max_coefficients, 1, 1 << 20)?;
        crate::fit::spec::within("within_points", self.within_points, 0.0, 100.0)?;
        Tolerance::check_relative(self.held_out_rel)
    }
}

/// A table the study compresses: its result file, its lobe (`None`: GGX) and the
/// transform sets tried (name, per channel a, b, c, d, norm, fresnel).
struct Source {
    table: &'static str,
    lobe: Option<Lobe>,
    transforms: [(&'static str, [Transform; 6]); 2],
    /// The transform set (index into `transforms`) the lobe fit starts from.
    lobe_fit: usize,
}

use Transform::{Log, OverAlpha, Raw};

const SOURCES: [Source; 3] = [
    Source {
        table: crate::results::names::LTC_GGX,
        lobe: None,
        // b and d vanish like α as α → 0 (the lobe's width): over α(r) their series stay
        // O(1) and their absolute error shrinks with the lobe
        transforms: [
            ("raw", [Raw; 6]),
            ("over-α", [Raw, OverAlpha, Raw, OverAlpha, Raw, Raw]),
        ],
        lobe_fit: 1,
    },
    Source {
        table: "ltc-sheen",
        lobe: Some(Lobe::SheenEstevezKulla),
        // the sheen norm spans 18 decades, so a raw fit is no candidate: its absolute
        // error swamps the lobes of albedo ≈ 0 (a quick run measured rel. L2 ≈ 1e14 there)
        transforms: [
            ("log", [Raw, Raw, Raw, Log, Log, Raw]),
            ("log-a", [Log, Raw, Raw, Log, Log, Raw]),
        ],
        lobe_fit: 0,
    },
    Source {
        table: "ltc-sheen-neubelt",
        lobe: Some(Lobe::SheenNeubelt),
        // the same decades of norm as the Estevez–Kulla table
        transforms: [
            ("log", [Raw, Raw, Raw, Log, Log, Raw]),
            ("log-a", [Log, Raw, Raw, Log, Log, Raw]),
        ],
        lobe_fit: 0,
    },
];

/// What the study computed.
pub struct Computed {
    result: crate::results::ltc_compact::LtcCompact,
}

/// The study.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let compare = crate::results::compare::read(c.results)?;
    let mut families = Vec::new();
    for s in &SOURCES {
        crate::report::stage(&format!("regen ltc-compact: {}", s.table));
        let shipped = if s.lobe.is_none() {
            compare.as_ref()
        } else {
            None
        };
        families.push(match s.lobe {
            None => family(c.results, s, &GgxTarget::new, &pl, shipped)?,
            Some(l) => family(c.results, s, &move |a, t| l.target(a, t), &pl, None)?,
        });
    }
    Ok(Computed {
        result: crate::results::ltc_compact::LtcCompact {
            spec: c.spec.clone(),
            command: crate::results::command(&c.spec.name),
            preset: c.preset.name().into(),
            every: pl.every,
            held_out_rel: pl.held_out_rel,
            families,
        },
    })
}

/// A judged place: cell or square (i, j).
#[derive(Clone, Copy)]
struct Place {
    square: bool,
    i: usize,
    j: usize,
}

impl Place {
    fn rt(&self, n: usize) -> (f64, f64) {
        let off = if self.square { 0.5 } else { 0.0 };
        let d = (n - 1) as f64;
        ((self.i as f64 + off) / d, (self.j as f64 + off) / d)
    }
    fn entries(&self, t: &Shipped) -> Option<([f64; 4], f64)> {
        if self.square {
            square_entries(t, self.i, self.j)
        } else {
            let k = self.i + t.n * self.j;
            Some((t.mat[k], t.mag[k][0]))
        }
    }
}

/// One table's forms, judged (see the module doc).
fn family<T: LtcTarget>(
    results: &std::path::Path,
    s: &Source,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    pl: &Plan,
    compare: Option<&crate::results::compare::LtcCompare>,
) -> Result<CompactFamily> {
    let table = crate::results::ltc::table(results, s.table)?;
    let grid: crate::ltc::fit::Grid = {
        #[derive(serde::Deserialize)]
        struct G {
            grid: crate::ltc::fit::Grid,
        }
        crate::results::require_named::<G>(results, s.table)?.grid
    };
    let n = table.n;
    if grid.n != n {
        return Err(Error::InvalidArgument(format!(
            "results/fits/{}.json: a {n}×{n} table under a grid of side {}",
            s.table, grid.n
        )));
    }
    let (forms, traces) = forms_of(&table, grid.alpha_min, s, target, pl)?;
    let full = stored_half(&table);
    let rebuilt: Vec<Shipped> = forms
        .iter()
        .map(|(_, f)| Ok(stored_half(&f.rebuild(n)?)))
        .collect::<Result<_>>()?;
    let f32c: Vec<Vec<Vec<f32>>> = forms.iter().map(|(_, f)| f.coeffs_f32()).collect();
    let places: Vec<Place> = [false, true]
        .into_iter()
        .flat_map(|square| {
            let w = if square { n - 1 } else { n };
            (0..w).step_by(pl.every).flat_map(move |j| {
                (0..w)
                    .step_by(pl.every)
                    .map(move |i| Place { square, i, j })
            })
        })
        .collect();
    let tol = Tolerance::relative(pl.held_out_rel);
    // keyed by the table's bits: the study reads the published file, not its study's run
    let label = format!(
        "ltc-compact {} {} (every {})",
        s.table,
        table.fingerprint(),
        pl.every
    );
    // per place: [full, then per form: rebuilt, texture-free]
    let judged: Vec<Vec<Option<LobeError>>> = crate::memo::map_items(&label, &places, |pc| {
        let (r, t) = pc.rt(n);
        let lobe = target(
            (r * r).max(grid.alpha_min),
            (1.0 - t * t).clamp(0.0, 1.0).acos(),
        )?;
        let (albedo, _, _) = lobe.albedo(1e-8);
        let mut entries: Vec<([f64; 4], f64)> = Vec::with_capacity(1 + 2 * forms.len());
        entries.push(pc.entries(&full).unwrap_or(([f64::NAN; 4], f64::NAN)));
        for (q, (_, f)) in forms.iter().enumerate() {
            entries.push(pc.entries(&rebuilt[q]).unwrap_or(([f64::NAN; 4], f64::NAN)));
            let e = f.eval_f32(&f32c[q], r as f32, t as f32).map(f64::from);
            entries.push(([e[0], e[1], e[2], e[3]], e[4]));
        }
        Ok(cell_error_of(&lobe, albedo, &entries, tol))
    })?;
    let split = |col: usize| {
        let figs: Vec<Option<LobeError>> = judged.iter().map(|v| v[col]).collect();
        judged_of(&places, &figs)
    };
    let paths = shipped_paths(compare, n, &places);
    let shipped: Vec<ShippedPath> = paths
        .iter()
        .map(|(path, r_min, figs)| ShippedPath {
            path: path.clone(),
            r_min: *r_min,
            full_vs_shipped: against(&judged, 0, figs),
            shipped: judged_of(&places, figs),
            ours_full: judged_of(
                &places,
                &judged
                    .iter()
                    .zip(figs)
                    .map(|(v, s)| s.and(v[0]))
                    .collect::<Vec<_>>(),
            ),
        })
        .collect();
    let out_forms: Vec<CompactForm> = forms
        .iter()
        .enumerate()
        .map(|(q, (name, f))| {
            let col = 1 + 2 * q;
            CompactForm {
                transforms: name.clone(),
                p: f.p,
                coefficients: f.coefficients(),
                rebuilt: split(col),
                texture_free: split(col + 1),
                rebuilt_worse_than_full: judged.iter().filter(|v| worse(&v[col], &v[0])).count(),
                rebuilt_vs_shipped: paths
                    .iter()
                    .map(|(_, _, figs)| against(&judged, col, figs))
                    .collect(),
                f32_rel_error: f32_error(f, &f32c[q]),
                lobe_fit: traces[q].clone(),
            }
        })
        .collect();
    let full_j = split(0);
    let chosen = choose(&out_forms, &full_j, pl);
    let texture_free =
        crate::results::ltc_compact::texture_free_form(&out_forms, pl.max_coefficients).map(|k| {
            TextureFree {
                form: k,
                series: forms[k].1.clone(),
            }
        });
    let series = forms[crate::results::ltc_compact::series_form(&out_forms, chosen).unwrap_or(0)]
        .1
        .clone();
    Ok(CompactFamily {
        table: s.table.into(),
        n,
        full_coefficients: 6 * n * n,
        full: full_j,
        shipped,
        forms: out_forms,
        chosen,
        series,
        texture_free,
        polygons: polygons::measure(results, s.table, &table, &forms)?,
        table_fingerprint: Some(table.fingerprint()),
    })
}

/// A table's compact forms: every transform set at every degree by least squares, then
/// the lobe fits (`ltc::compact_fit`, each memoised) of the source's lobe-fit set; with
/// each form's lobe-fit trace (`None` for least squares).
#[allow(clippy::type_complexity)]
fn forms_of<T: LtcTarget>(
    table: &crate::ltc::table::FittedTable,
    alpha_min: f64,
    s: &Source,
    target: &(dyn Fn(f64, f64) -> Result<T> + Sync),
    pl: &Plan,
) -> Result<(Vec<(String, Compact)>, Vec<Option<Trace>>)> {
    let n = table.n;
    let mut forms: Vec<(String, Compact)> = Vec::new();
    for (name, tr) in &s.transforms {
        for &p in &pl.degrees {
            forms.push((
                name.to_string(),
                Compact::fit_scaled(&table, p, *tr, alpha_min)?,
            ));
        }
    }
    let mut traces: Vec<Option<Trace>> = vec![None; forms.len()];
    let plan = LobeFit {
        nodes: pl.lobe_nodes,
        iterations: pl.lobe_iterations,
        passes: pl.lobe_passes,
    };
    {
        let (name, tr) = &s.transforms[s.lobe_fit];
        for &p in &pl.lobe_degrees {
            if p > n {
                return Err(Error::InvalidArgument(format!(
                    "fits/ltc-compact.toml: lobe degree {p} exceeds the {} table's side {n}",
                    s.table
                )));
            }
            let start = Compact::fit_scaled(&table, p, *tr, alpha_min)?;
            let label = format!(
                "ltc-compact lobe fit {} {} {name} p {p}",
                s.table,
                table.fingerprint()
            );
            let (fitted, trace) = crate::memo::map(&label, 1, |_| {
                refine(&start, n, alpha_min, target, plan, s.table)
            })?
            .remove(0);
            forms.push((format!("{name}, lobe-fit"), fitted));
            traces.push(Some(trace));
        }
    }
    Ok((forms, traces))
}

/// Whether figure `a` is worse (higher relative L2) than `b` by more than both bars; a
/// missing `a` against a present `b` is worse.
fn worse(a: &Option<LobeError>, b: &Option<LobeError>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => a.l2.value > b.l2.value + a.l2.error + b.l2.error,
        (None, Some(_)) => true,
        _ => false,
    }
}

/// Column `col` of the judged places against other figures at the same places: how many
/// are better, tied, worse (beyond both bars); places without a figure in `figs` are left
/// out.
fn against(
    judged: &[Vec<Option<LobeError>>],
    col: usize,
    figs: &[Option<LobeError>],
) -> [usize; 3] {
    let mut c = [0usize; 3];
    for (v, s) in judged.iter().zip(figs) {
        if s.is_none() {
            continue;
        }
        if worse(&v[col], s) {
            c[2] += 1;
        } else if worse(s, &v[col]) {
            c[0] += 1;
        } else {
            c[1] += 1;
        }
    }
    c
}

/// The shipped table's figures at the judged places, per engine path of
/// results/ltc-compare.json (`None` where the path does not reach a place).
fn shipped_paths(
    compare: Option<&crate::results::compare::LtcCompare>,
    n: usize,
    places: &[Place],
) -> Vec<(String, f64, Vec<Option<LobeError>>)> {
    let Some(c) = compare else { return Vec::new() };
    c.forms
        .iter()
        .filter(|f| f.cells.len() == n * n && f.squares.len() == (n - 1) * (n - 1))
        .filter(|f| f.name.contains("Half") || f.name.contains("Bevy"))
        .map(|f| {
            let figs = places
                .iter()
                .map(|p| {
                    let pair = if p.square {
                        &f.squares[p.i + (n - 1) * p.j]
                    } else {
                        &f.cells[p.i + n * p.j]
                    };
                    pair.shipped
                })
                .collect();
            (f.name.clone(), f.r_min, figs)
        })
        .collect()
}

fn judged_of(places: &[Place], figs: &[Option<LobeError>]) -> Judged {
    let of = |sq: bool| {
        Spread::of(
            places
                .iter()
                .zip(figs)
                .filter(|(p, _)| p.square == sq)
                .map(|(_, v)| v.as_ref().map(|e| &e.l2)),
        )
    };
    Judged {
        cells: of(false),
        squares: of(true),
    }
}

/// The largest |f32 − f64| / max(|f64|, 1e-3) of any channel over a 257² grid.
fn f32_error(f: &Compact, c32: &[Vec<f32>]) -> f64 {
    let m = 256;
    let mut worst: f64 = 0.0;
    for j in 0..=m {
        for i in 0..=m {
            let (r, t) = (i as f64 / m as f64, j as f64 / m as f64);
            let a = f.eval(r, t);
            let b = f.eval_f32(c32, r as f32, t as f32);
            for ch in 0..6 {
                let e = (f64::from(b[ch]) - a[ch]).abs() / a[ch].abs().max(1e-3);
                worst = worst.max(e);
            }
        }
    }
    worst
}

/// The form with the fewest coefficients meeting the goal: within `max_coefficients`, no
/// place worse than the shipped table on any path (when a path was judged), and a mean
/// (cells and squares) within `within_points` of the full table's.
fn choose(forms: &[CompactForm], full: &Judged, pl: &Plan) -> Option<usize> {
    let near = |a: &Spread, b: &Spread| a.mean.value - b.mean.value <= pl.within_points / 100.0;
    (0..forms.len())
        .filter(|&k| {
            let f = &forms[k];
            f.coefficients <= pl.max_coefficients
                && f.rebuilt_vs_shipped.iter().all(|c| c[2] == 0)
                && near(&f.rebuilt.cells, &full.cells)
                && near(&f.rebuilt.squares, &full.squares)
        })
        .min_by_key(|&k| forms[k].coefficients)
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut crate::io::Outputs, results: &std::path::Path) -> Result<()> {
        let name = &self.result.spec.name;
        set.put(
            &results.join(format!("{name}.md")),
            report::markdown(&self.result).as_bytes(),
        );
        set.put(
            &results.join(format!("{name}.svg")),
            report::plot(&self.result)?.as_bytes(),
        );
        crate::results::put(set, results, &self.result)
    }

    fn outcome(&self) -> FitOutcome {
        let f = &self.result.families;
        let best = f
            .iter()
            .flat_map(|f| f.forms.iter().map(|x| x.rebuilt.cells.mean.value))
            .fold(f64::INFINITY, f64::min);
        FitOutcome::measured(
            &self.result.spec,
            best,
            f.iter()
                .map(|f| {
                    format!(
                        "{}: {}",
                        f.table,
                        match f.chosen {
                            Some(k) => format!(
                                "{} coefficients meet the goal ({} p = {})",
                                f.forms[k].coefficients, f.forms[k].transforms, f.forms[k].p
                            ),
                            None => "no form meets the goal".into(),
                        }
                    )
                })
                .collect::<Vec<_>>()
                .join("; "),
        )
    }
}

crate::study::study! {
    /// Compact LTC tables, as the registry holds it.
    LtcCompactStudy = "ltc-compact", after [], on request true, params Plan, computes compute
}
