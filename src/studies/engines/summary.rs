//! What the engines report states of a run, computed from its result: per engine and
//! path, the scenes where ours renders closer to the truth or further from it (beyond
//! both error bars) and the means over the scenes, each within the mean of its bars.

use super::compute::{EngineResult, EnginesResult, PathResult, SceneResult};
use crate::integrate::{Figure, Quad};
use serde::Serialize;

impl EngineResult {
    /// The mean over scenes of a figure of one (table, path), within the mean of its bars.
    pub fn mean(
        &self,
        table: &str,
        path: &str,
        f: impl Fn(&PathResult) -> Figure<Quad>,
    ) -> Figure<Quad> {
        let v: Vec<Figure<Quad>> = self
            .scenes
            .iter()
            .flat_map(|s| {
                s.paths
                    .iter()
                    .filter(|x| x.table == table && x.path == path)
            })
            .map(f)
            .collect();
        Figure::<Quad>::mean_bounded(&v)
    }
}

/// A scene where ours renders further from the truth than the shipped table, beyond both
/// error bars, with both tables' figures: the engine's and the tables' own shares.
#[derive(Clone, Debug, Serialize)]
pub struct Worse {
    pub scene: String,
    pub ours: Figure<Quad>,
    pub shipped: Figure<Quad>,
    pub ours_table: Figure<Quad>,
    pub shipped_table: Figure<Quad>,
}

impl Worse {
    /// Whether our table's own share is the larger: the table is the cause, not the
    /// engine's shader.
    pub fn table_is_cause(&self) -> bool {
        self.ours_table.value > self.shipped_table.value
    }
}

/// One path of one engine over its scenes, as the report states it.
#[derive(Clone, Debug, Serialize)]
pub struct PathSummary {
    pub path: &'static str,
    pub scenes: usize,
    /// Scenes where ours renders closer to the truth (relative RMSE, beyond both bars).
    pub better: Vec<String>,
    pub worse: Vec<Worse>,
    /// Mean relative RMSE over the scenes (± the mean of the scenes' bars), the engine
    /// with the shipped table and with ours…
    pub shipped_mean: Figure<Quad>,
    pub ours_mean: Figure<Quad>,
    /// …and the tables' own shares.
    pub shipped_table_mean: Figure<Quad>,
    pub ours_table_mean: Figure<Quad>,
    /// The largest relative RMSE of the engine against its formulas in f64 (f32 arithmetic,
    /// filtering), over scenes and tables.
    pub gpu_max: f64,
    /// Every other table rendered (three.js: the compact drop-in), against the shipped one.
    pub others: Vec<OtherTable>,
}

/// A table beyond the shipped one and ours on one path: its means over the scenes and the
/// scenes where it renders closer to the truth than the shipped table, or further from it
/// (relative RMSE, beyond both error bars).
#[derive(Clone, Debug, Serialize)]
pub struct OtherTable {
    pub table: &'static str,
    pub mean: Figure<Quad>,
    pub table_mean: Figure<Quad>,
    pub better_than_shipped: Vec<String>,
    pub worse_than_shipped: Vec<String>,
}

/// What the report states of a run, computed from its result (results/engines.json holds
/// it beside the result).
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The truth's largest relative error bar over every engine's pixels.
    pub truth_bar: f64,
    /// Per engine (in the result's order), per path.
    pub paths: Vec<Vec<PathSummary>>,
    /// Godot's mean relative RMSE over the scenes (± the mean of the scenes' bars): its
    /// formulas, its table's share.
    pub godot_means: Option<(Figure<Quad>, Figure<Quad>)>,
}

fn mean(v: impl Iterator<Item = Figure<Quad>>) -> Figure<Quad> {
    Figure::<Quad>::mean_bounded(&v.collect::<Vec<_>>())
}

impl EngineResult {
    /// One scene's figures of one (table, path).
    pub fn find(s: &SceneResult, table: &str, path: &str) -> Option<PathResult> {
        s.paths
            .iter()
            .find(|x| x.table == table && x.path == path)
            .cloned()
    }

    /// The scenes where `table` renders closer to the truth than the shipped table on
    /// `path`, and those where it renders further (relative RMSE, beyond both bars).
    fn against_shipped(&self, table: &str, path: &str) -> (Vec<String>, Vec<String>) {
        let (mut better, mut worse) = (Vec::new(), Vec::new());
        for s in &self.scenes {
            let (Some(a), Some(b)) = (
                EngineResult::find(s, table, path),
                EngineResult::find(s, "shipped", path),
            ) else {
                continue;
            };
            let (o, t) = (a.engine.rel_rmse, b.engine.rel_rmse);
            if o.value + o.error < t.value - t.error {
                better.push(s.name.clone());
            } else if o.value - o.error > t.value + t.error {
                worse.push(s.name.clone());
            }
        }
        (better, worse)
    }

    /// One path over the scenes.
    pub fn path_summary(&self, path: &'static str) -> PathSummary {
        let (better, worse) = self.against_shipped("ours", path);
        let worse = self
            .scenes
            .iter()
            .filter(|s| worse.contains(&s.name))
            .filter_map(|s| {
                let (a, b) = (
                    EngineResult::find(s, "ours", path)?,
                    EngineResult::find(s, "shipped", path)?,
                );
                Some(Worse {
                    scene: s.name.clone(),
                    ours: a.engine.rel_rmse,
                    shipped: b.engine.rel_rmse,
                    ours_table: a.table_share.rel_rmse,
                    shipped_table: b.table_share.rel_rmse,
                })
            })
            .collect();
        PathSummary {
            path,
            scenes: self.scenes.len(),
            better,
            worse,
            shipped_mean: self.mean("shipped", path, |x| x.engine.rel_rmse),
            ours_mean: self.mean("ours", path, |x| x.engine.rel_rmse),
            shipped_table_mean: self.mean("shipped", path, |x| x.table_share.rel_rmse),
            ours_table_mean: self.mean("ours", path, |x| x.table_share.rel_rmse),
            gpu_max: self
                .scenes
                .iter()
                .flat_map(|s| s.paths.iter().filter(|x| x.path == path))
                .map(|x| x.gpu_share.rel_rmse.value)
                .fold(0.0, f64::max),
            others: self
                .tables
                .iter()
                .filter(|t| !["shipped", "ours"].contains(t))
                .map(|&table| {
                    let (better_than_shipped, worse_than_shipped) =
                        self.against_shipped(table, path);
                    OtherTable {
                        table,
                        mean: self.mean(table, path, |x| x.engine.rel_rmse),
                        table_mean: self.mean(table, path, |x| x.table_share.rel_rmse),
                        better_than_shipped,
                        worse_than_shipped,
                    }
                })
                .collect(),
        }
    }
}

impl EnginesResult {
    /// Everything the report states beyond the result's own figures.
    pub fn summary(&self) -> Summary {
        Summary {
            truth_bar: self
                .engines
                .iter()
                .flat_map(|e| &e.scenes)
                .map(|s| s.truth_rel_error)
                .fold(0.0, f64::max),
            paths: self
                .engines
                .iter()
                .map(|e| e.paths.iter().map(|p| e.path_summary(p)).collect())
                .collect(),
            godot_means: (!self.godot.is_empty()).then(|| {
                (
                    mean(self.godot.iter().map(|s| s.formulas.rel_rmse)),
                    mean(self.godot.iter().map(|s| s.table_share.rel_rmse)),
                )
            }),
        }
    }
}
