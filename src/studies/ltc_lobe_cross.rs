//! `regen --only ltc-lobe-cross` (on request): what it costs to shade one lobe of a table
//! family with the other lobe's table, or with no table at all. Kept out of the main job:
//! it judges tables that are already published, so the tables' own studies pay only for
//! their fit and its measures.
//!
//! Per family (`ltc::lobes::family`: the sheen pair, the diffuse pair), cell by cell on the
//! held-out integrals (`ltc::lobe_error`, to the tolerance the main table was judged to):
//! - the main table against the variant's lobe, and the variant's table against the main
//!   lobe, each table with its own norm;
//! - the clamped cosine (M = I) with weight 1 (Lambert, what an engine without the table
//!   shades area lights with) and with the table's norm (energy-correct Lambert), against
//!   the main lobe;
//! - on the cells whose albedo exceeds 1, the main table with its norm clamped to 1 (a
//!   bounded table), beside the true table on the same cells.
//!
//! Reads results/fits/<family>.json and its variant's; writes results/ltc-lobe-cross.md
//! and results/fits/ltc-lobe-cross.json.

use crate::error::{Error, Result};
use crate::fit::spec::FitSpec;
use crate::integrate::Preset;
use crate::io::Outputs;
use crate::ltc::compare::cell_error_of;
use crate::ltc::fit::Grid;
use crate::ltc::lobe_error::{LobeError, Tolerance};
use crate::ltc::lobes::{family, Family, Lobe};
use crate::ltc::table::FittedTable;
use crate::results::lobe_cross::{Bounded, FamilyCross, LobeCross};
use crate::results::ltc::Located;
use crate::study::{Ctx, FitOutcome};

/// What fits/ltc-lobe-cross.toml sets.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// The table families judged, by their spec names (ltc-sheen, ltc-diffuse).
    pub families: Vec<String>,
}

impl crate::fit::spec::Params for Plan {
    fn check(&self) -> std::result::Result<(), String> {
        if self.families.is_empty() {
            return Err("families: empty (name ltc-sheen, ltc-diffuse or both)".into());
        }
        for (k, f) in self.families.iter().enumerate() {
            if family(f).is_none() {
                return Err(format!(
                    "families: {} is no LTC table family (ltc-sheen, ltc-diffuse)",
                    crate::error::quoted(f)
                ));
            }
            if self.families[..k].contains(f) {
                return Err(format!("families: {} named twice", crate::error::quoted(f)));
            }
        }
        Ok(())
    }
}

/// What the study computed.
pub struct Computed {
    spec: FitSpec,
    preset: Preset,
    families: Vec<(Family, FamilyCross)>,
}

/// The study: each family's published tables, judged against each other's lobes.
pub fn compute(c: &Ctx) -> Result<Computed> {
    let pl: Plan = c.params()?;
    let mut families = Vec::new();
    for name in &pl.families {
        let fam = family(name).ok_or_else(|| {
            Error::InvalidArgument(format!("fits/{}.toml: no family {name}", c.spec.name))
        })?;
        crate::report::stage(&format!("regen ltc-lobe-cross: {}", fam.name));
        families.push((fam, judge_family(c.results, &fam)?));
    }
    Ok(Computed {
        spec: c.spec.clone(),
        preset: c.preset,
        families,
    })
}

/// One published table with its grid and fingerprint.
struct Read {
    table: FittedTable,
    grid: Grid,
    fingerprint: String,
    tolerance: Tolerance,
}

fn read(results: &std::path::Path, name: &str) -> Result<Read> {
    let (p, table, fingerprint) = crate::results::ltc::published_table(results, name)?;
    Ok(Read {
        table,
        grid: p.grid,
        fingerprint,
        tolerance: p.route(name)?.tolerance(),
    })
}

fn judge_family(results: &std::path::Path, fam: &Family) -> Result<FamilyCross> {
    const COSINE: [f64; 4] = [1.0, 0.0, 0.0, 1.0];
    let main = read(results, fam.name)?;
    let variant = read(results, fam.variant_name)?;
    let g = (main.grid.n, main.grid.alpha_min);
    if (variant.grid.n, variant.grid.alpha_min) != g {
        return Err(Error::InvalidArgument(format!(
            "results/fits/{}.json: its grid ({}, α ≥ {}) is not that of results/fits/{}.json ({}, α ≥ {}): run `cargo run --release -- regen --only {}`",
            fam.variant_name, variant.grid.n, variant.grid.alpha_min, fam.name, g.0, g.1, fam.name
        )));
    }
    let tol = main.tolerance;
    let full = |c: &[f64; 6]| ([c[0], c[1], c[2], c[3]], c[4]);
    let vt = &variant.table;
    // against the main lobe, per main cell: the variant's table, Lambert with weight 1,
    // Lambert with the norm; where the albedo exceeds 1, the main table with its norm
    // clamped to 1 and with its true norm (elsewhere both are the table itself)
    let on_main = against(
        "other tables against the main lobe",
        &main,
        fam.main,
        &|k, c| {
            let mut e = vec![full(&vt.cells[k]), (COSINE, 1.0), (COSINE, c[4])];
            if c[4] > 1.0 {
                e.extend([(full(c).0, 1.0), full(c)]);
            }
            e
        },
        tol,
    )?;
    let mt = &main.table;
    let on_variant = against(
        "main table against the variant lobe",
        &variant,
        fam.variant,
        &|k, _| vec![full(&mt.cells[k])],
        tol,
    )?;
    // the columns over the cells whose albedo exceeds 1 (none: no such column)
    let bounded_cells: Vec<usize> = (0..mt.cells.len())
        .filter(|&k| mt.cells[k][4] > 1.0)
        .collect();
    let where_bounded = |q: usize| -> Located {
        let rows: Vec<_> = bounded_cells.iter().map(|&k| on_main[q][k]).collect();
        Located::of(&rows)
    };
    Ok(FamilyCross {
        family: fam.name.into(),
        main_table: fam.name.into(),
        variant_table: fam.variant_name.into(),
        fingerprints: [main.fingerprint, variant.fingerprint],
        main_table_for_variant: Located::of(&on_variant[0]),
        variant_table_for_main: Located::of(&on_main[0]),
        cosine_unit_for_main: Located::of(&on_main[1]),
        cosine_norm_for_main: Located::of(&on_main[2]),
        bounded: (!bounded_cells.is_empty()).then(|| Bounded {
            cells: bounded_cells.len(),
            bounded: where_bounded(3),
            true_table: where_bounded(4),
        }),
    })
}

/// The entries judged at cell k of a table (k = i + n·j, given its stored cell): each a
/// production-form M⁻¹ with its amplitude.
type Entries<'a> = dyn Fn(usize, &[f64; 6]) -> Vec<([f64; 4], f64)> + Sync + 'a;

/// Per cell of a table, its figures (`None` where it has none) and its (α, θ°).
type Judged = Vec<(Option<LobeError>, (f64, f64))>;

/// Every cell of the published table `t` against `lobe` at its (α, θ): the held-out
/// figures of each of the entries `entries(k, cell)` (judged together, in one cubature
/// per cell; k = i + n·j). `t` must be `lobe`'s own table: the target's chart is weighed
/// by the cell's norm, the albedo its fit integrated (as the held-out stage,
/// `ltc::held`, does). Per entry, every cell's figures (`None` where a cell has fewer
/// entries or a singular matrix) with its (α, θ°).
fn against(
    label: &str,
    t: &Read,
    lobe: Lobe,
    entries: &Entries<'_>,
    tol: Tolerance,
) -> Result<Vec<Judged>> {
    let (n, cells) = (t.grid.n, &t.table.cells);
    let place = |k: usize| (t.grid.alpha(k % n), t.grid.theta(k / n));
    let errs: Vec<Vec<Option<LobeError>>> = crate::memo::map(label, cells.len(), |k| {
        let (alpha, theta) = place(k);
        let tgt = lobe.target(alpha, theta)?;
        Ok(cell_error_of(
            &tgt,
            cells[k][4],
            &entries(k, &cells[k]),
            tol,
        ))
    })?;
    let most = errs.iter().map(|e| e.len()).max().unwrap_or(0);
    Ok((0..most)
        .map(|q| {
            errs.iter()
                .enumerate()
                .map(|(k, e)| {
                    let (alpha, theta) = place(k);
                    (e.get(q).copied().flatten(), (alpha, theta.to_degrees()))
                })
                .collect()
        })
        .collect())
}

fn family_section(fam: &Family, c: &FamilyCross) -> String {
    let (m, v) = (fam.main.short(), fam.variant.short());
    let mut md = format!(
        "## {}\n\nTables: results/fits/{}.json ({m}) and results/fits/{}.json ({v}).\n\n- the {m} table against the {v} lobe: {};\n- the {v} table against the {m} lobe: {};\n",
        fam.title,
        c.main_table,
        c.variant_table,
        c.main_table_for_variant.words(),
        c.variant_table_for_main.words(),
    );
    if matches!(fam.main, Lobe::BurleyPaper | Lobe::BurleyEngines) {
        md.push_str(&format!(
            "- the clamped cosine (M = I) with weight 1 (Lambert, as Bevy shades area lights' diffuse) against the {m} lobe: {};\n",
            c.cosine_unit_for_main.words()
        ));
    }
    md.push_str(&format!(
        "- the clamped cosine with the table's norm (energy-correct, no table but the norm) against the {m} lobe: {}.\n\n",
        c.cosine_norm_for_main.words()
    ));
    if let Some(b) = &c.bounded {
        md.push_str(&format!(
            "A bounded table (for an engine that wants no weight above 1: the {m} table with its norm clamped to 1) differs only on the {} cells whose albedo exceeds 1; there it costs: {} against the true table's {}. The true table stays the one shipped; the bounded one is the same files with the norm channel clamped.\n\n",
            b.cells,
            b.bounded.words(),
            b.true_table.words()
        ));
    }
    md
}

fn markdown(c: &Computed) -> String {
    let mut md = format!(
        "# One lobe shaded with the other's table, or with none\n\nWritten by `{}` (preset {}) from `fits/{}.toml`, on request (the main job leaves it out). It reads each family's published tables and judges them cell by cell on the held-out integrals of the tables' own studies (`ltc::lobe_error`, to the tolerance the main table was judged to), each table with its own norm, at every cell of the main table's grid. Each figure is a mean or a largest over the cells, ± its bar (the mean of the cells' bars; the largest's own).\n\n",
        crate::results::command(&c.spec.name),
        c.preset.name(),
        c.spec.name,
    );
    for (fam, fc) in &c.families {
        md.push_str(&family_section(fam, fc));
    }
    md
}

impl crate::study::Computed for Computed {
    fn render(&self, set: &mut Outputs, results: &std::path::Path) -> Result<()> {
        set.put(
            results.join(format!("{}.md", self.spec.name)),
            markdown(self).as_bytes(),
        );
        crate::results::put(
            set,
            results,
            &LobeCross {
                spec: self.spec.clone(),
                command: crate::results::command(&self.spec.name),
                preset: self.preset.name().into(),
                families: self.families.iter().map(|f| f.1.clone()).collect(),
            },
        )
    }

    fn outcome(&self) -> FitOutcome {
        let worst = self
            .families
            .iter()
            .map(|f| f.1.variant_table_for_main.l2.mean.value)
            .fold(0.0, f64::max);
        let summary = self
            .families
            .iter()
            .map(|(fam, c)| {
                format!(
                    "{}: the {} table for the {} lobe {}, the reverse {} mean rel. L2",
                    fam.name,
                    fam.variant.short(),
                    fam.main.short(),
                    c.variant_table_for_main.l2.mean.pct(2),
                    c.main_table_for_variant.l2.mean.pct(2)
                )
            })
            .collect::<Vec<_>>()
            .join("; ");
        FitOutcome::measured(&self.spec, worst, summary)
    }
}

crate::study::study! {
    /// The cost of shading one lobe with the other's table, as the registry holds it.
    LtcLobeCross = "ltc-lobe-cross", after ["ltc-sheen", "ltc-diffuse"], on request true, params Plan, computes compute
}
