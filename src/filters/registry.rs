//! The footprint filters: the one list of them in the crate. Every other place that names
//! a filter reads it from here by key: the footprint study and its reports (seed 004
//! §3.2; seed 003), `eval filter`, `prefilter --filter`, the `render` study's method sets
//! and the `scene` options.
//!
//! A filter is one of three kinds:
//! - a **map filter** ([`MAP`]): α′ from the base α and the mip's mean-normal length
//!   r = ‖μ‖ (or, for LEAN, its slope covariance);
//! - a **screen-space kernel** ([`SCREEN`]): α′ from the base α and a 2×2 pixel quad's
//!   derivatives of the normal (or, for the forward kernels, of the half-vector);
//! - a **refitted** filter ([`REFIT`]): a map filter or kernel whose constant the footprint
//!   study fits (results/fits/filters.json `fitted`, GGX) instead of the paper's.
//!
//! Each entry carries its key (unique over all three lists), its report label, its rule
//! (the f64 reference and the f32 shading form are the same generic code in
//! [`super::rules`], instantiated at each precision), and where it exists: its generated
//! shading function (`src/generated/shading.rs`, WGSL), its criterion bench id, and its
//! entry in the footprint study's per-filter summary.

pub use super::rules::{MapRule, ScreenRule};
use crate::error::{Error, Result};

/// Where a filter appears outside the footprint study: its generated shading function,
/// its criterion bench id (`benches/filters.rs`, "filters/<id>") and its key in the
/// study's per-filter summary (results/fits/filters.json `summary`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Uses {
    pub shader: Option<&'static str>,
    pub bench: Option<&'static str>,
    pub summary: Option<&'static str>,
}

const fn uses(
    shader: Option<&'static str>,
    bench: Option<&'static str>,
    summary: Option<&'static str>,
) -> Uses {
    Uses {
        shader,
        bench,
        summary,
    }
}

const NONE: Uses = uses(None, None, None);

/// One map filter: its key, its report label, its rule, the survey family and parameters
/// per texel it is listed under, whether its lobe is one of the importance-sampling
/// proposals of every map case, and where else it appears.
#[derive(Clone, Copy, Debug)]
pub struct MapFilter {
    pub key: &'static str,
    pub label: &'static str,
    pub rule: MapRule,
    pub family: &'static str,
    pub params: usize,
    pub proposes: bool,
    pub uses: Uses,
}

const fn mf(
    key: &'static str,
    label: &'static str,
    rule: MapRule,
    (family, params, proposes): (&'static str, usize, bool),
    uses: Uses,
) -> MapFilter {
    MapFilter {
        key,
        label,
        rule,
        family,
        params,
        proposes,
        uses,
    }
}

/// The map filters, in report order: the footprint study's results are indexed like this
/// list; code finds a filter by key ([`map_index`]). The engines' tool rules come last and
/// propose no lobe: their lobes lie between the vMF variants', and the defensive mixture
/// covers every lobe, so adding them left the other filters' numbers unchanged.
pub static MAP: [MapFilter; 12] = [
    mf(
        "mip-normal",
        "none (renormalised mip normal)",
        MapRule::Renormalised,
        ("none", 2, true),
        uses(None, None, Some("none-map")),
    ),
    mf(
        "toksvig-bp",
        "Toksvig, Blinn–Phong form",
        MapRule::ToksvigBp,
        ("Toksvig", 3, true),
        uses(None, None, Some("toksvig-bp")),
    ),
    mf(
        "toksvig-2",
        "Toksvig α² + 2σ²",
        MapRule::Toksvig(2.0),
        ("Toksvig", 3, true),
        uses(Some("filter_toksvig"), Some("toksvig"), Some("toksvig")),
    ),
    mf(
        "toksvig-1",
        "Toksvig α² + σ²",
        MapRule::Toksvig(1.0),
        ("Toksvig", 3, true),
        NONE,
    ),
    mf(
        "vmf-2",
        "vMF α² + 2/κ",
        MapRule::Vmf(2.0),
        ("vMF rules", 3, true),
        uses(Some("filter_vmf"), Some("vmf"), Some("vmf")),
    ),
    mf(
        "vmf-1",
        "vMF α² + 1/κ",
        MapRule::Vmf(1.0),
        ("vMF rules", 3, true),
        NONE,
    ),
    mf(
        "vmf-half",
        "vMF α² + 1/(2κ)",
        MapRule::Vmf(0.5),
        ("vMF rules", 3, true),
        NONE,
    ),
    mf(
        "lean",
        "LEAN (Eq 19: A = α²I + 2Σ, mean slope)",
        MapRule::Lean,
        ("LEAN", 5, true),
        uses(None, None, Some("lean")),
    ),
    mf(
        "seed000-eq5-eq7",
        "seed 000 Eq 5 + Eq 7",
        MapRule::Seed000Paper,
        ("seed 000", 3, true),
        uses(None, None, Some("seed000-paper")),
    ),
    mf(
        "seed000-moment",
        "seed 000 moment: ρ⁻¹(‖μ‖ρ(α))",
        MapRule::Moment,
        ("seed 000", 3, true),
        uses(
            Some("multiscale_alpha"),
            Some("seed000-moment"),
            Some("seed000-moment"),
        ),
    ),
    mf(
        "filament-prefilter",
        "Filament roughness-prefilter: α + 2/κ",
        MapRule::Filament,
        ("engines", 3, false),
        uses(None, None, Some("filament")),
    ),
    mf(
        "godot-limiter",
        "Godot roughness limiter: α + min(0.75/κ, 0.16)",
        MapRule::Godot,
        ("engines", 3, false),
        uses(None, None, Some("godot")),
    ),
];

/// One screen-space kernel: its key, its report label, its rule, where else it appears.
#[derive(Clone, Copy, Debug)]
pub struct ScreenFilter {
    pub key: &'static str,
    pub label: &'static str,
    pub rule: ScreenRule,
    pub uses: Uses,
}

const fn sf(key: &'static str, label: &'static str, rule: ScreenRule, uses: Uses) -> ScreenFilter {
    ScreenFilter {
        key,
        label,
        rule,
        uses,
    }
}

const INF: f64 = f64::INFINITY;

/// The screen-space kernels, in report order: the footprint study's results are indexed
/// like this list; code finds a kernel by key ([`screen_index`]).
pub static SCREEN: [ScreenFilter; 12] = [
    sf(
        "none",
        "none",
        ScreenRule::None,
        uses(None, None, Some("none-screen")),
    ),
    sf(
        "tokuyoshi-deferred",
        "Tokuyoshi deferred (Eq 13, σ² 0.25, δ 0.18)",
        ScreenRule::Deferred {
            s2: 0.25,
            delta: 0.18,
        },
        uses(Some("filter_deferred"), Some("deferred"), Some("deferred")),
    ),
    sf(
        "eq13-unclamped",
        "Eq 13 without the clamp",
        ScreenRule::Deferred {
            s2: 0.25,
            delta: INF,
        },
        NONE,
    ),
    sf(
        "eigen-eq10",
        "exact eigenvalue (Eq 10, σ² 0.25, δ 0.18)",
        ScreenRule::Eigen {
            s2: 0.25,
            delta: 0.18,
        },
        uses(Some("filter_eq10"), Some("eigen"), Some("eigen")),
    ),
    sf(
        "kaplanyan-rect",
        "Kaplanyan rect (Listing 3, intended)",
        ScreenRule::KaplanyanRect {
            s2: 0.25,
            delta: 0.18,
        },
        uses(None, None, Some("rect")),
    ),
    sf(
        "filament",
        "Filament (0.15 / 0.04)",
        ScreenRule::Deferred {
            s2: 0.15,
            delta: 0.04,
        },
        NONE,
    ),
    sf(
        "unity-hdrp",
        "Unity HDRP (0.1 / 0.04)",
        ScreenRule::Deferred {
            s2: 0.1,
            delta: 0.04,
        },
        NONE,
    ),
    sf(
        "unity-projected",
        "Unity projected space (0.1 / 0.04)",
        ScreenRule::ProjectedSpace {
            s2: 0.1,
            delta: 0.04,
        },
        uses(
            Some("filter_projected"),
            Some("projected"),
            Some("projected"),
        ),
    ),
    sf(
        "godot",
        "Godot (0.25 / 0.18 on α)",
        ScreenRule::DeferredOnAlpha {
            s2: 0.25,
            delta: 0.18,
        },
        uses(None, None, Some("on-alpha")),
    ),
    sf(
        "eq10-unclamped",
        "Eq 10 without the clamp",
        ScreenRule::Eigen {
            s2: 0.25,
            delta: INF,
        },
        NONE,
    ),
    sf(
        "kaplanyan-forward",
        "Kaplanyan forward (slope space, Eq 2–3)",
        ScreenRule::Forward { slope: true },
        NONE,
    ),
    sf(
        "tokuyoshi-forward",
        "Tokuyoshi forward (projected disk, Eq 7)",
        ScreenRule::Forward { slope: false },
        uses(None, None, Some("forward")),
    ),
];

/// A filter whose constant the footprint study refits: the rule of `base` (a key of
/// [`MAP`] or [`SCREEN`]) with the constant of the GGX fit named `family` in
/// results/fits/filters.json `fitted` (vMF's and Toksvig's c, the kernels' σ²).
#[derive(Clone, Copy, Debug)]
pub struct Refitted {
    pub key: &'static str,
    /// The label before the constant ("…, refitted c = 1.864").
    pub label: &'static str,
    pub base: &'static str,
    pub family: &'static str,
    pub uses: Uses,
}

/// The refitted filters.
pub static REFIT: [Refitted; 5] = [
    Refitted {
        key: "vmf-refit",
        label: "vMF α² + c/κ, refitted c",
        base: "vmf-2",
        family: "vMF α² + c/κ",
        uses: uses(Some("filter_vmf_fitted"), Some("vmf"), None),
    },
    Refitted {
        key: "toksvig-refit",
        label: "Toksvig α² + c·σ², refitted c",
        base: "toksvig-2",
        family: "Toksvig α² + c·σ²",
        uses: NONE,
    },
    Refitted {
        key: "eq13-refit-gaussian",
        label: "Eq 13, σ² refitted (Gaussian pixel)",
        base: "tokuyoshi-deferred",
        family: "Eq 13 σ² (Gaussian pixel)",
        uses: uses(Some("filter_deferred_fitted"), Some("deferred"), None),
    },
    Refitted {
        key: "eq13-refit-box",
        label: "Eq 13, σ² refitted (box pixel)",
        base: "tokuyoshi-deferred",
        family: "Eq 13 σ² (box pixel)",
        uses: NONE,
    },
    Refitted {
        key: "godot-refit-box",
        label: "Godot's form, σ² refitted (box pixel)",
        base: "godot",
        family: "kernel on α σ² (box pixel)",
        uses: NONE,
    },
];

/// The place of the map filter `key` in [`MAP`] (results are indexed like it). The keys
/// are this module's constants; an unknown one is a programming error.
pub fn map_index(key: &str) -> usize {
    MAP.iter()
        .position(|f| f.key == key)
        .unwrap_or_else(|| panic!("no map filter {key:?}"))
}

/// The place of the kernel `key` in [`SCREEN`] (results are indexed like it). The keys are
/// this module's constants; an unknown one is a programming error.
pub fn screen_index(key: &str) -> usize {
    SCREEN
        .iter()
        .position(|f| f.key == key)
        .unwrap_or_else(|| panic!("no screen kernel {key:?}"))
}

/// Whether a filter works on a mip's statistics or on a pixel quad's derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    Map,
    Screen,
}

/// A filter's rule: the map rule or the kernel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rule {
    Map(MapRule),
    Screen(ScreenRule),
}

/// Any filter of the registry, found by key.
#[derive(Clone, Copy, Debug)]
pub enum Filter {
    Map(&'static MapFilter),
    Screen(&'static ScreenFilter),
    Refit(&'static Refitted),
}

impl PartialEq for Filter {
    fn eq(&self, other: &Filter) -> bool {
        self.key() == other.key()
    }
}

impl serde::Serialize for Filter {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.key())
    }
}

impl Filter {
    /// Every filter: the map filters, the kernels, then the refitted ones.
    pub fn all() -> impl Iterator<Item = Filter> {
        MAP.iter()
            .map(Filter::Map)
            .chain(SCREEN.iter().map(Filter::Screen))
            .chain(REFIT.iter().map(Filter::Refit))
    }

    /// The filter of `key`, if there is one.
    pub fn find(key: &str) -> Option<Filter> {
        Filter::all().find(|f| f.key() == key)
    }

    /// The filter of `key`; a typed error listing the valid keys otherwise. `what` names
    /// where the key came from (an option, a scene key).
    pub fn get(key: &str, what: &str) -> Result<Filter> {
        Filter::find(key).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "{what}: no footprint filter {}; valid: {}",
                crate::error::quoted(key),
                Filter::all()
                    .map(|f| f.key())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }

    /// The filter of a key this crate spells as a constant (a programming error if absent).
    pub fn of(key: &str) -> Filter {
        Filter::find(key).unwrap_or_else(|| panic!("no footprint filter {key:?}"))
    }

    pub fn key(self) -> &'static str {
        match self {
            Filter::Map(f) => f.key,
            Filter::Screen(f) => f.key,
            Filter::Refit(f) => f.key,
        }
    }

    /// The report label (a refitted filter's without its constant: see [`Filter::label_with`]).
    pub fn label(self) -> &'static str {
        match self {
            Filter::Map(f) => f.label,
            Filter::Screen(f) => f.label,
            Filter::Refit(f) => f.label,
        }
    }

    /// The label with a refitted filter's constant.
    pub fn label_with(self, constant: Option<f64>) -> String {
        match (self, constant) {
            (Filter::Refit(_), Some(c)) => format!("{}: {c:.4}", self.label()),
            _ => self.label().to_string(),
        }
    }

    pub fn uses(self) -> Uses {
        match self {
            Filter::Map(f) => f.uses,
            Filter::Screen(f) => f.uses,
            Filter::Refit(f) => f.uses,
        }
    }

    /// The fitted family whose constant a refitted filter takes.
    pub fn family(self) -> Option<&'static str> {
        match self {
            Filter::Refit(f) => Some(f.family),
            _ => None,
        }
    }

    /// The filter whose rule this one uses (itself unless refitted).
    pub fn base(self) -> Filter {
        match self {
            Filter::Refit(f) => Filter::of(f.base),
            f => f,
        }
    }

    pub fn domain(self) -> Domain {
        match self.base() {
            Filter::Screen(_) => Domain::Screen,
            _ => Domain::Map,
        }
    }

    /// The rule as printed (a refitted filter's with its base's constant).
    pub fn rule(self) -> Rule {
        match self.base() {
            Filter::Map(f) => Rule::Map(f.rule),
            Filter::Screen(f) => Rule::Screen(f.rule),
            Filter::Refit(_) => {
                unreachable!("a refitted filter's base is a map filter or a kernel")
            }
        }
    }

    /// The rule with a refitted filter's constant from `fitted` (the family's GGX
    /// constant); a typed error when a refitted filter's constant is missing or not finite.
    pub fn rule_with(self, fitted: impl Fn(&str) -> Option<f64>) -> Result<Rule> {
        let Some(family) = self.family() else {
            return Ok(self.rule());
        };
        let c = fitted(family).filter(|c| c.is_finite() && *c > 0.0).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "filter {}: results/fits/filters.json has no finite GGX constant for {} (the footprint study writes it)",
                self.key(),
                crate::error::quoted(family)
            ))
        })?;
        Ok(match self.rule() {
            Rule::Map(r) => Rule::Map(r.with_constant(c)),
            Rule::Screen(r) => Rule::Screen(r.with_constant(c)),
        })
    }
}
