//! The index of results/: every output, the command that writes it and the spec it reads,
//! as data. results/README.md is rendered from it (`cargo run --release -- results-readme`),
//! and tests/results.rs holds the index to the folder: every committed file is listed, every
//! entry names a file that exists, and a file that says which command wrote it says the
//! same command as its entry.

/// The command that writes results/README.md.
pub const README_COMMAND: &str = "cargo run --release -- results-readme";

/// Who writes an output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Writer {
    /// A study of the registry: `regen --only NAME` (and the main job), reading
    /// fits/NAME.toml.
    Study(&'static str),
    /// A step of `regen` after the studies, from the fitted results (no spec of its own).
    AfterStudies,
    /// Another command, given in full, with the inputs it reads.
    Command(&'static str, &'static str),
}

impl Writer {
    /// The command line that rewrites the output.
    pub fn command(&self) -> String {
        match self {
            Writer::Study(s) => format!("cargo run --release -- regen --only {s}"),
            Writer::AfterStudies => "cargo run --release -- regen".into(),
            Writer::Command(c, _) => c.to_string(),
        }
    }

    /// What it reads: the spec, or the inputs named by the command.
    pub fn reads(&self) -> String {
        match self {
            Writer::Study(s) => format!("fits/{s}.toml"),
            Writer::AfterStudies => "results/fits/*.json".into(),
            Writer::Command(_, r) => r.to_string(),
        }
    }
}

/// One output: a path under results/ (a trailing `*` matches any rest of the name, within
/// one folder unless the pattern ends in `**`), who writes it, and what it is.
#[derive(Clone, Copy, Debug)]
pub struct Output {
    pub path: &'static str,
    pub by: Writer,
    pub what: &'static str,
}

const fn o(path: &'static str, by: Writer, what: &'static str) -> Output {
    Output { path, by, what }
}

use Writer::{AfterStudies, Command, Study};

const ENGINES: Writer = Command(
    "cargo run --release -- engines --three-shipped target/engines/three-shipped.json --three-ours target/engines/three-ours.json --three-compact target/engines/three-compact.json --bevy-shipped target/engines/bevy-shipped.json --bevy-ours target/engines/bevy-ours.json",
    "the engines' renders (engines/three, engines/bevy-check)",
);
const ENGINES_SHEEN: Writer = Command(
    "cargo run --release -- engines-sheen --three target/engines/three-sheen.json --three target/engines/three-sheen-ggx-scenes.json",
    "the three.js sheen runs (engines/three: node render.mjs --table sheen --scenes scenes_sheen.json, and on scenes.json)",
);
const LTC_COMPARE: Writer = Command(
    "cargo run --release -- ltc-compare --shipped target/shipped/RectAreaLightTexturesLib.js --bevy target/shipped/bevy_ltc.ktx2",
    "the shipped three.js and Bevy tables, results/fits/ltc-ggx.json",
);
const BENCH: Writer = Command(
    "cargo bench --bench engines && cargo run --release -- bench-report",
    "criterion's target/criterion, results/",
);
const VERIFY: Writer = Command(
    "cargo run --release -- verify --preset default",
    "proofs/*.md",
);
const CONVERGENCE: Writer = Command("cargo run --release -- convergence --preset default", "—");
const FUZZ: Writer = Command(
    "PROPTEST_CASES=100000 NDFB_FUZZ_OUT=results/fuzz cargo test --release --test fuzz",
    "tests/fuzz.rs",
);
const SCENES: Writer = Command(
    "cargo run --release -- scene <file> --out DIR",
    "tests/scenes/*.toml, each run by `regen`",
);
const README: Writer = Command(README_COMMAND, "src/results/index.rs");
const KEPT: Writer = Command(
    "— (kept as measured)",
    "the sequential, uncached main job of an earlier version",
);

/// Every output of results/, grouped by writer.
pub const OUTPUTS: &[Output] = &[
    o("README.md", README, "this index"),
    o("smith-lambda.md", Study("smith-lambda"), "Beckmann Smith Λ: the refitted rational against Walter's"),
    o("smith-lambda.svg", Study("smith-lambda"), "its error curves"),
    o("fits/smith-lambda.json", Study("smith-lambda"), "the fitted coefficients and held-out errors"),
    o("leadr-grids.md", Study("leadr-grids"), "LEADR N×N slope grids against the reference"),
    o("leadr-pareto.svg", Study("leadr-grids"), "error against grid size"),
    o("fits/leadr-grids.json", Study("leadr-grids"), "the fitted spacings and errors"),
    o("multiscale-alpha-me.md", Study("multiscale-alpha-me"), "α_me from ‖b̄‖ (seed 000 §3.3): fits, held-out errors, Eq 5 audit"),
    o("multiscale-alpha-me.svg", Study("multiscale-alpha-me"), "α_me against ‖b̄‖"),
    o("multiscale-alpha-error.svg", Study("multiscale-alpha-me"), "each method's error in α"),
    o("fits/multiscale-alpha-me.json", Study("multiscale-alpha-me"), "the fitted α_me coefficients"),
    o("multiscale-convolution.md", Study("multiscale-convolution"), "the overall α of γ_me ∗ γ_mi under every metric, Eq 7 refitted"),
    o("multiscale-convolution.svg", Study("multiscale-convolution"), "slices of the overall α"),
    o("multiscale-convolution-maps.svg", Study("multiscale-convolution"), "error maps of each model"),
    o("fits/multiscale-convolution.json", Study("multiscale-convolution"), "the refitted constants"),
    o("filters.md", Study("filters"), "footprint roughness filters against the footprint-averaged BRDF"),
    o("filters-*.svg", Study("filters"), "per-map and screen-space error plots; the survey's plot"),
    o("filters-survey.md", Study("filters"), "seed 004's pre-filtering representations on the same cases"),
    o("fits/filters.json", Study("filters"), "the fitted filter constants and per-filter summaries"),
    o("ltc-ggx.md", Study("ltc-ggx"), "the GGX LTC table, its held-out errors, polygon lights, storage precision"),
    o("ltc-error.svg", Study("ltc-ggx"), "the table's held-out error per cell"),
    o("fits/ltc-ggx.json", Study("ltc-ggx"), "the GGX LTC table"),
    o("ltc-ggx-optimisers.md", Study("ltc-ggx-optimisers"), "the GGX fit's diagnostics: its route against the reference route cell by cell, optimiser variants, the floor of a single LTC (on request only)"),
    o("fits/ltc-ggx-optimisers.json", Study("ltc-ggx-optimisers"), "its figures"),
    o("ltc-work.md", Study("ltc-work"), "the LTC tables' accuracy against their fitting work: each published route's own spread over training draws, and cheaper routes judged against it (on request only)"),
    o("fits/ltc-work.json", Study("ltc-work"), "its figures"),
    o("ltc-aniso-work.md", Study("ltc-aniso-work"), "the anisotropic table's accuracy against its fitting work: the reference route's own spread over training draws, and cheaper routes (fixed nodes, lower caps) judged against it (on request only)"),
    o("fits/ltc-aniso-work.json", Study("ltc-aniso-work"), "its figures"),
    o("ltc-judge-tolerance.md", Study("ltc-judge-tolerance"), "the held-out judge's accuracy against its work per LTC table: the curve each table's tolerance is chosen from (on request only)"),
    o("ltc-judge-tolerance.svg", Study("ltc-judge-tolerance"), "its plot: the bars and the largest change against evaluations per cell"),
    o("fits/ltc-judge-tolerance.json", Study("ltc-judge-tolerance"), "its figures"),
    o("ltc-between-sample.md", Study("ltc-between-sample"), "the between-cell sample's accuracy against its work per LTC table: every square judged, the sample redrawn; the curve the sample size is chosen from (on request only)"),
    o("ltc-between-sample.svg", Study("ltc-between-sample"), "its plot: the mean s.e. and the share of draws within 2 s.e. against squares judged"),
    o("fits/ltc-between-sample.json", Study("ltc-between-sample"), "its figures"),
    o("ltc-compact.md", Study("ltc-compact"), "the GGX and sheen tables as compact Chebyshev series, fitted to the entries or by the lobe error after bilinear reading: coefficients against the exact lobe error, rebuilt and texture-free, beside the full and shipped tables (on request only; its GGX series becomes wgsl/ltc_compact.wgsl, textures/three/ltc_compact.js and src/generated/ltc_compact.rs; its sheen tables' texture-free picks become wgsl/ltc_sheen.wgsl, glsl/ltc_sheen.glsl, the three.js recipe textures/three/RectAreaLightSheen.js and src/generated/ltc_sheen.rs)"),
    o("ltc-compact.svg", Study("ltc-compact"), "its plot: mean held-out error against coefficient count"),
    o("fits/ltc-compact.json", Study("ltc-compact"), "its figures and the GGX and sheen series (the form the goal chose, else the most accurate rebuild)"),
    o("ltc-sheen.md", Study("ltc-sheen"), "the Charlie sheen LTC tables (both visibility conventions)"),
    o("ltc-sheen-error.svg", Study("ltc-sheen"), "their held-out error per cell"),
    o("fits/ltc-sheen*.json", Study("ltc-sheen"), "the sheen tables"),
    o("ltc-diffuse.md", Study("ltc-diffuse"), "the Burley diffuse LTC tables"),
    o("ltc-diffuse-error.svg", Study("ltc-diffuse"), "their held-out error per cell"),
    o("fits/ltc-diffuse*.json", Study("ltc-diffuse"), "the diffuse tables"),
    o("ltc-lobe-cross.md", Study("ltc-lobe-cross"), "one lobe shaded with the other's table of its family, with Lambert or with a bounded table, cell by cell (on request only)"),
    o("fits/ltc-lobe-cross.json", Study("ltc-lobe-cross"), "its figures"),
    o("ltc-aniso.md", Study("ltc-aniso"), "the anisotropic GGX LTC table against the isotropic one"),
    o("ltc-aniso*.svg", Study("ltc-aniso"), "its design study and error plots"),
    o("fits/ltc-aniso.json", Study("ltc-aniso"), "the anisotropic table"),
    o("tensor.md", Study("tensor"), "seed 002: P-NDF images, CP compression, range queries, sampling, the shading cost of Table 3"),
    o("tensor-rank.svg", Study("tensor"), "error against CP rank"),
    o("fits/tensor.json", Study("tensor"), "the tensor study's figures"),
    o("tensor-scale.md", Study("tensor-scale"), "seed 002 at the paper's scale (on request only)"),
    o("fits/tensor-scale.json", Study("tensor-scale"), "its figures"),
    o("tensor-envsg.md", Study("tensor-envsg"), "seed 002 §5.4: environment lighting as spherical Gaussians — the SG fit of a procedural sky, and the prefiltered NDF query (Eq 8–9) against point queries and the quadrature truth over ε and scale (on request only)"),
    o("tensor-envsg.svg", Study("tensor-envsg"), "the relative MSE of a 16-sample pixel against the query square's scale, per ε"),
    o("tensor-envsg-picture.svg", Study("tensor-envsg"), "seed 002 Fig 11 on a flat patch: truth, point query and prefiltered query, one pixel per footprint"),
    o("fits/tensor-envsg.json", Study("tensor-envsg"), "its figures"),
    o("tensor-wang.md", Study("tensor-wang"), "seed 002 §5.5: Wang tiles for constant storage — seams, the tiles' images against the explicit map's (Fig 14), per-tile CP, storage and query cost (on request only)"),
    o("tensor-wang.svg", Study("tensor-wang"), "seed 002 Fig 14: one footprint's NDF image from the explicit map and from its tiles, and their difference"),
    o("fits/tensor-wang.json", Study("tensor-wang"), "its figures"),
    o("tensor-wave.md", Study("tensor-wave"), "seed 002 §3.1: wave-optics NDF images checked against the FFT, Parseval and the geometric limit, in colour, CP-compressed (on request only)"),
    o("tensor-wave.svg", Study("tensor-wave"), "the distance to the geometric limit against the wavelength"),
    o("fits/tensor-wave.json", Study("tensor-wave"), "its figures"),
    o("visibility.md", Study("visibility"), "seed 004 §4–6, §8.1: horizons, shadowing, procedural pre-filtering"),
    o("visibility.svg", Study("visibility"), "error against parameters per texel"),
    o("fits/visibility.json", Study("visibility"), "the visibility study's figures"),
    o("render.md", Study("render"), "rendered evidence: every method against the per-pixel truth"),
    o("render/*.png", Study("render"), "the figure grids and strips"),
    o("fits/render.json", Study("render"), "the render errors"),
    o("render-truth-work.md", Study("render-truth-work"), "the render truth's accuracy against its work: texels drawn per replicate on large footprints against every texel, the curve each scene's truth_draws is chosen from (on request only)"),
    o("render-truth-work.svg", Study("render-truth-work"), "its plot: the truth's variance against texel shadings per pixel"),
    o("fits/render-truth-work.json", Study("render-truth-work"), "its figures"),
    o("wgsl/*", AfterStudies, "the generated WGSL modules (naga-validated)"),
    o("glsl/*", AfterStudies, "the generated GLSL ES 3.00 functions: the texture-free sheen LTCs (glslang-validated)"),
    o("shaders/naga_oil/*", AfterStudies, "the same modules for naga_oil's composer"),
    o("shaders/wesl/*", AfterStudies, "the same modules as WESL"),
    o("textures/**", AfterStudies, "the LTC tables as engine files: KTX2, DDS, raw f16/f32, ES modules, the three.js and Godot drop-ins"),
    o("generated-range.md", AfterStudies, "every generated function over its whole input range"),
    o("shaders.md", AfterStudies, "every module through naga's back ends and the validators"),
    o("shaders/spv/*", AfterStudies, "the SPIR-V of every module"),
    o("scenes/**", SCENES, "the example scenes: shader, Rust twin, report"),
    o("proofs.md", VERIFY, "every numerical proof: worst error against its tolerance"),
    o("proofs.json", VERIFY, "the same, as data"),
    o("convergence.*", CONVERGENCE, "the integration engines' error against work"),
    o("performance.md", BENCH, "criterion's times beside each approximation's error; the main job's profile"),
    o("costs.json", BENCH, "ns per evaluation, read by scene selection"),
    o("error-vs-time.svg", BENCH, "error against time per integration engine"),
    o("kernels-speedup.svg", BENCH, "AVX2 against scalar per kernel"),
    o("ltc-compact-cost.svg", BENCH, "the compact LTC tables: held-out error against SPIR-V instructions per pixel, texture-free series and texture lookup"),
    o("main-job-before.json", KEPT, "the main job's stages before parallel studies and the cache"),
    o("engines.*", ENGINES, "LTC tables rendered in three.js and Bevy against the truth (three.js also with the compact drop-in)"),
    o("engines-sheen.*", ENGINES_SHEEN, "the sheen alone under RectAreaLight in three.js, as shipped and with our texture-free recipe, against the truth"),
    o("ltc-compare*", LTC_COMPARE, "our GGX table against the shipped ones, as engines sample them"),
    o(
        "tensor-tensorly.json",
        Command("cargo run --release -- tensorly-compare", "TensorLy 0.10.0 (pip)"),
        "our CP-ALS against TensorLy's",
    ),
    o("fuzz/*", FUZZ, "the fuzz campaigns' counts per input kind"),
];

/// Whether `rel` (a path under results/, `/`-separated) is the output `pattern`.
pub fn matches(pattern: &str, rel: &str) -> bool {
    if let Some(dir) = pattern.strip_suffix("**") {
        return rel.starts_with(dir);
    }
    match pattern.split_once('*') {
        None => pattern == rel,
        Some((head, tail)) => {
            rel.len() >= head.len() + tail.len()
                && rel.starts_with(head)
                && rel.ends_with(tail)
                && !rel[head.len()..rel.len() - tail.len()].contains('/')
        }
    }
}

/// The entry of `rel`: the first that matches.
pub fn entry(rel: &str) -> Option<&'static Output> {
    OUTPUTS.iter().find(|o| matches(o.path, rel))
}

/// results/README.md.
pub fn readme() -> String {
    let mut md = format!(
        "<!-- @generated by `{README_COMMAND}` from src/results/index.rs; do not edit. -->\n\
         # results/\n\n\
         Everything here is written by the workbench; nothing is edited by hand. The main job \
         (`cargo run --release`) rewrites every study's outputs (tensor-envsg's, tensor-scale's, tensor-wang's, tensor-wave's, ltc-ggx-optimisers', ltc-lobe-cross', ltc-work's, ltc-aniso-work's, ltc-judge-tolerance's and render-truth-work's only when named) and the steps after them; the \
         other commands are run on request. Each study reads its spec in fits/ and writes its \
         report (`NAME.md`, named as the spec), its plots and its typed result \
         (`fits/NAME.json`).\n\n"
    );
    let mut t = crate::report::table::Table::new(["output", "what", "written by", "reads"]);
    for o in OUTPUTS {
        t.row([
            format!("`{}`", o.path),
            o.what.to_string(),
            format!("`{}`", o.by.command()),
            o.by.reads().to_string(),
        ]);
    }
    md.push_str(&t.to_string());
    md
}
