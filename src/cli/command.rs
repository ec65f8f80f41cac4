//! The command line: every subcommand and option with its help text (docs/cli.md is
//! generated from these), parsed by clap; `main.rs` dispatches.

use crate::integrate::Preset;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "ndfbench",
    version,
    about = "Numerical verification and fitting workbench for microfacet NDF prefiltering and specular antialiasing.\n\nWith no subcommand: regenerate every fit, verify every proof and write results/ at the default preset.",
    long_about = "Numerical verification and fitting workbench for microfacet NDF prefiltering and specular antialiasing.\n\nWith no subcommand, the main job: `regen` of every spec in `fits/`, `verify` at the default preset, then the convergence study; writes `results/fits/*.json`, the fits' reports, `results/proofs.{md,json}` and `results/convergence.{md,json,svg}`. Exit 1 if a proof fails or a fit misses its held-out tolerance. Every subcommand has its own --help; docs/cli.md holds them all."
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Option<Cmd>,
    /// Directory that receives results.
    #[arg(long, default_value = "results", global = true)]
    pub results: PathBuf,
    /// Directory holding the fit specifications.
    #[arg(long, default_value = "fits", global = true)]
    pub fits: PathBuf,
    /// The main job's result cache (memoised maps keyed by the hash of the code the study
    /// reaches, the spec, the preset and the inputs).
    #[arg(long, default_value = "target/ndfbench-cache", global = true)]
    pub cache: PathBuf,
    /// The main job computes everything (no cache lookups, nothing stored).
    #[arg(long, global = true)]
    pub no_cache: bool,
}

#[derive(Subcommand)]
pub enum Cmd {
    /// Run the fit specifications of fits/ and write results/fits/*.json and their reports;
    /// exit 1 if a held-out error misses its spec's tolerance.
    ///
    /// Usage: `regen [--only NAME[,NAME…]] [--preset quick|default|precise]`. Runs the fit
    /// specifications of `fits/` (strict TOML: each study reads its `[params]`, with the
    /// `[quick]` or `[precise]` table over them; a key it does not read, a missing key or
    /// a value out of bounds is an error naming the file and the key, at every preset,
    /// before anything runs);
    /// `--only` takes exact spec names (a study that follows others brings them along; any
    /// other text is an error listing the valid names) and writes
    /// `results/fits/<name>.json` (coefficients, held-out max/RMS error) and the fit's
    /// report (a markdown file of `results/` and its SVG plots). `--only ltc-ggx` fits the
    /// 64×64 GGX LTC table (four parameters per cell) and measures polygon integration,
    /// the multi-scale pipeline and what f32/f16 storage costs (`results/ltc-ggx.md`; its
    /// fit's diagnostics — optimiser variants, the floor of a single LTC, the route
    /// against the reference route — run on request, `--only ltc-ggx-optimisers`; the cost of shading a sheen or diffuse lobe with
    /// the other lobe's table or with Lambert, on request, `--only ltc-lobe-cross`; the LTC tables' accuracy against fitting work, cheaper routes
    /// judged against each published route's own spread over training draws, `--only ltc-work`, and the anisotropic table's, `--only ltc-aniso-work`; every cell's held-out figures are judged as exact integrals,
    /// to the tolerance each table's spec chooses from the curve of `--only ltc-judge-tolerance`, on request;
    /// the error between cells over every square, the GGX table judging all, the sheen and diffuse a calibrated sample whose size
    /// comes from the curve of `--only ltc-between-sample`, on request;
    /// results/performance.md has each study's wall clock), and writes the
    /// engine files (`results/textures/`); `--only tensor` CP-compresses P-NDF image blocks
    /// at several ranks (`results/tensor.md`); `--only tensor-scale` runs seed 002
    /// at the paper's scale (`results/tensor-scale.md`; on request only,
    /// never part of the main job or of a selection of other studies); `--only tensor-wave`
    /// checks and compresses seed 002's wave-optics NDF images (`results/tensor-wave.md`;
    /// on request only); `--only tensor-envsg` measures seed 002's SG environment
    /// prefiltering (`results/tensor-envsg.md`; on request only); `--only tensor-wang`
    /// builds and checks seed 002's Wang tiles
    /// (`results/tensor-wang.md`; on request only); `--only visibility`
    /// measures the horizon, shadow and procedural methods
    /// (`results/visibility.md`); `--only render-truth-work` measures the render truth's
    /// accuracy against its work, the curve each scene's `truth_draws` is chosen
    /// from (`results/render-truth-work.md`; on request only); `--only filters` runs the footprint-filter group
    /// (LEADR grids, Smith Λ refit, footprint filters, and on the same cases the survey's
    /// pre-filtering representations) and writes `results/filters.md` and
    /// `results/filters-survey.md` with progress bars. Every regen then regenerates the code: WGSL
    /// modules under `results/wgsl/` (including the LTC table as data: `ltc_table.wgsl`
    /// f32, `ltc_table_f16.wgsl` binary16) and, for the canonical `results/`, the Rust
    /// twins in `src/generated/shading.rs` and the table constants in
    /// `src/generated/ltc_table.rs` and the example scenes under `results/scenes/`, the
    /// importable forms (`results/shaders/{naga_oil,wesl}/`), and every module and scene
    /// shader through naga's four back ends and the validators (`results/shaders.md`,
    /// `results/shaders/spv/`); a test fails when any of them is stale. Exit 1 if a
    /// held-out error misses its spec's tolerance.
    ///
    /// Usage: `regen --only NAME --shard K/N [--shard-dir DIR] [--preset …]`. Computes
    /// shard K of N (items i ≡ K mod N) of the study's first memoised map — the LTC
    /// studies' θ columns, the convolution study's per-pair fits — and writes only
    /// `DIR/NAME.shard-K-of-N.json` (default `shards/`) with the study, the code version,
    /// the hashes of its spec and of its inputs, the preset and the items. The studies it
    /// follows must already be in `--results`. A study without a memoised map is an error.
    ///
    /// Usage: `regen … --cached`, `regen … --parallel`. Look every memoised map up in the
    /// cache (`--cache DIR`, default `target/ndfbench-cache`) under the SHA-256 of the
    /// code the study reaches (its own files and those it imports, found by the build
    /// script: an edit to another study, a report it does not use, the driver or a test
    /// leaves it warm), the spec, the preset and the inputs (a miss computes and stores
    /// it; a hit gives the same bits, `tests/shard.rs`, `tests/cache_keys.rs`); run
    /// studies whose inputs are ready at the same time. The main job does both;
    /// `--no-cache` makes it compute everything.
    Regen {
        /// Run only these studies: exact spec names, comma-separated (e.g.
        /// `ltc-ggx,ltc-sheen`); a study that follows others brings them along.
        #[arg(long)]
        only: Option<String>,
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
        /// Compute only shard K of N (K/N, 0 ≤ K < N) of the study's first memoised map
        /// and write it to --shard-dir; needs --only with the study's exact name.
        #[arg(long)]
        shard: Option<String>,
        /// Where --shard writes its file.
        #[arg(long, default_value = "shards")]
        shard_dir: PathBuf,
        /// Look memoised maps up in (and store them to) the cache given by --cache.
        #[arg(long)]
        cached: bool,
        /// Run studies whose inputs are ready at the same time.
        #[arg(long)]
        parallel: bool,
    },
    /// Merge a complete set of shard files (files or directories) into the study's
    /// results, exactly what the unsharded run writes; a missing, duplicated or foreign
    /// shard is an error and nothing is written.
    ///
    /// Files or directories of shard files → checks that the set is complete and consistent
    /// (one study, code version, spec, input set, preset and N; every K once; each file
    /// exactly its own items) and writes exactly what the unsharded `regen --only NAME`
    /// writes (bit for bit: `tests/shard.rs`). A missing, duplicated, foreign or corrupt
    /// shard (each file carries the SHA-256 of its content, so one changed digit is caught)
    /// is a one-line error naming it, exit 2, nothing written.
    Merge {
        #[arg(required = true)]
        shards: Vec<PathBuf>,
    },
    /// Write a Slurm job array (one shard per task) and its dependent merge job.
    ///
    /// Writes a Slurm job array (`DIR/array.sbatch`, `--array=0-(N−1)%M`, one shard per
    /// task), the merge job (`DIR/merge.sbatch`) and `DIR/submit.sh`, which submits the
    /// array and the merge with `--dependency=afterok` (extra arguments go to the merge's
    /// `sbatch`, e.g. `--wait`). Paths are absolute; shard files go to `DIR/shards/`, logs
    /// to `DIR/logs/`.
    Slurm(super::batch::SlurmArgs),
    /// Check every identity of proofs/ numerically; write results/proofs.md; exit 1 on failure.
    ///
    /// `--only` takes exact check ids (the stems of proofs/*.md). Checks every identity of
    /// `proofs/` numerically; prints one line per check (worst error, tolerance, time) and,
    /// without `--only`, writes `results/proofs.md` and `results/proofs.json`. Exit status
    /// 1 if any check fails; 2 if `--only` names no check. `precise` spends more
    /// evaluations per check than `default`.
    Verify {
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
        /// Run only these checks: exact ids (the stems of proofs/*.md), comma-separated.
        #[arg(long)]
        only: Option<String>,
    },
    /// Convergence study of the engines (error vs evaluations) → results/convergence.{md,svg}.
    ///
    /// Error against integrand evaluations for MC, MIS, RQMC, Gauss–Legendre and adaptive
    /// GK on three integrands with closed forms; fitted orders; table and log–log plot.
    Convergence {
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
    },
    /// Evaluate one model quantity and print JSON (for scripting). See `eval --help`.
    ///
    /// Evaluates one model quantity and prints JSON (for scripting). Quantities: `d`,
    /// `p22`, `lambda`, `nu`, `g1`, `g2-correlated`, `g2-separable`, `vndf-pdf`,
    /// `jacobian`, `mrl` (‖b̄‖ of the isotropic LTC, `--alpha`, any positive f64),
    /// `alpha-me` (`--b` or `--one-minus-b`, `--method paper|ours|table|newton`; fitted
    /// methods report their held-out error, and `inside_domain` says whether the input lies
    /// in the fit's domain), `overall-alpha` (`--alpha-mi`, `--alpha-me`: the one-LTC fit
    /// of γ_me ∗ γ_mi under every metric, ~1 s of quadrature, when both lie in [1e-3, 3];
    /// elsewhere the closed-form moment metric, and the limit max(α_mi, α_me) when one is
    /// below 1e-3 of the other, with its error), `filter` (`--filter KEY --alpha A` plus
    /// the filter's inputs, KEY one of the footprint filters listed under `--filter`: `--b`
    /// = ‖μ‖ for the map filters, `--cov XX,YY,XY` for lean, `--dn-u`/`--dn-v` for the
    /// deferred kernels (tokuyoshi-deferred, filament, unity-hdrp, unity-projected, godot
    /// and their refits), `--du`/`--dv` for eigen-eq10, kaplanyan-rect and the forward
    /// kernels; refitted filters read their constant from results/fits/filters.json;
    /// prints the f64 α′ and the f32 shading form — the
    /// latter only where every input is an f32, otherwise `f32_note` says why). Surface:
    /// `--ndf ggx|beckmann`, one of `--alpha A`, `--alpha-xy AX,AY`, `--matrix
    /// A11,A12,A22`; optional `--mean MX,MY`, `--lambda
    /// exact|walter-printed|walter-listing`. Directions (normalised for you): `--o`, `--i`,
    /// `--m`, `--w` as `x,y,z`; `--slope x,y` for `p22`; `--map
    /// normal-to-slope|reflection|half-vector|slope-parallel|projected-disk` for
    /// `jacobian`.
    Eval(super::args::EvalArgs),
    /// Roughness mips from your normal map (PNG): the footprint variance of every mip
    /// folded into roughness by a measured rule, written as KTX2 (every level) and PNGs,
    /// with the normal mips and a report of the rule's measured error. With --study, the
    /// footprint-filter study on the map instead; with --rank, its P-NDF compression.
    ///
    /// Usage: `prefilter --input NORMAL.png (--roughness ROUGH.png | --alpha A) [--filter
    /// NAME] [--format r8|r16|r16f] [--layout r|gltf] [--store perceptual|alpha] [--normals
    /// renormalised|raw] [--channel auto|r|g|b|a] [--reconstruct-z] [--out DIR]`. Roughness
    /// mips an engine loads. The normal map (tangent space, OpenGL +Y, 8/16-bit RGB(A) PNG,
    /// power-of-two sides up to 8192, non-square allowed; `--reconstruct-z` for two-channel
    /// maps) gives per texel of every mip the mean of the unit normals under it, r = ‖μ‖;
    /// the rule turns r and the mean base roughness into α′: `best` (default: the measured
    /// rule with the smallest mean lobe error in `results/fits/filters.json`) or the key of
    /// a map filter (listed under `--filter`; `filament-prefilter` and `godot-limiter` are
    /// Filament's roughness-prefilter and Godot's import limiter as they ship). The roughness map holds perceptual roughness (α = value², glTF), grey or the
    /// G channel of RGB(A); it may be smaller than the normal map by a power of two along
    /// both axes, and each of its texels then covers that block (nearest) — the chain is
    /// written at the normal map's size, as three.js's RoughnessMipmapper does. Writes
    /// DIR/roughness.ktx2 (every level, R8_UNORM, R16_UNORM or R16_SFLOAT, a basic DFD) and
    /// roughness-L*.png, or with `--layout gltf` DIR/metallic_roughness.ktx2 (RGBA: R
    /// occlusion, G roughness, B metallic, the R and B box-mipped from an RGB(A) input) and
    /// metallic_roughness-L*.png; DIR/normal.ktx2 (RGBA8, or RGBA16 for 16-bit input) and
    /// normal-L*.png (renormalised unless `--normals raw`); DIR/prefilter.{md,json} with
    /// the rule, its measured error and every other rule's. Each level is the 2×2 average
    /// of the one above (O(N) for the chain). Bad input (broken or grey PNG, not a normal
    /// map, both or neither of `--roughness`/`--alpha`, α ∉ [1e-12, 1] (⟨α²⟩ is held in
    /// f32), a larger or differently shaped roughness map) is a typed error with nothing
    /// written.
    ///
    /// Usage: `prefilter --study --input MAP.png [--alpha A] [--preset …] [--out DIR]`. The
    /// footprint-filter study of `results/filters.md` on your normal map (its plan at the
    /// preset from fits/filters.toml, as this build compiled it in): per-filter
    /// energy/L2/peak errors with error bars against the footprint-averaged BRDF, the worst
    /// cases, an L2-vs-footprint plot and per-level α′ maps (vMF 2/κ).
    ///
    /// Usage: `prefilter (--input MAP.png | --generator NAME) --rank R [--out DIR]`. P-NDF
    /// images of the map (seed 002 Eq 2) over two footprint levels, with the block side t,
    /// image size, ALS settings and σ_r of fits/tensor.toml at the preset (as this build
    /// compiled it in), non-negative CP at rank R per spatial cluster (so the hierarchical
    /// sampler is exact) → DIR/tensor-<name>.json (factors, weights, errors),
    /// DIR/tensor-<name>.md (error and compression at R/4, R/2 and R) and
    /// DIR/tensor-<name>-rank.svg (error against rank); generators: isotropic-noise,
    /// brushed-metal, flakes, sharp-bumps, scratches; a rank above t², a missing file or a
    /// bad PNG is an error with nothing written.
    Prefilter(super::prefilter::PrefilterArgs),
    /// Write only the WGSL and Rust a scene needs (scene TOML), with a report of each
    /// chosen approximation's measured error and cost.
    ///
    /// Writes only the WGSL (`scene.wgsl`) and Rust (`scene.rs`) one scene needs and
    /// `report.md` with each chosen approximation's measured error and cost. Keys: `name`
    /// (1–64 characters of `[A-Za-z0-9_-]`, starting with a letter), `ndf` (ggx|beckmann),
    /// `roughness` (isotropic|anisotropic|matrix), `lights` (point, polygon — LTC table +
    /// quad integral, GGX isotropic —, environment — LEADR 5×5 grid, Beckmann),
    /// `normal_map_filter` (auto, mip-normal or the key of a map filter that ships a
    /// generated function; an unknown key is an error listing the valid ones),
    /// `screen_space_aa` (auto, none or the key of such a kernel), `precision` (f32; f16 is
    /// refused with the reason), `error_budget` (mean relative L2 lobe error; `auto` takes,
    /// of the options whose measured error + 1 s.e. meets it, the most accurate whose
    /// cost is not measurably above the cheapest's: 95 % intervals that meet). Unknown or
    /// contradictory keys are errors naming the key; the WGSL is validated with naga before
    /// anything is written. Examples: `tests/scenes/*.toml`, outputs in `results/scenes/`.
    Scene {
        /// scene file (TOML); see tests/scenes/ for examples
        file: PathBuf,
        /// output directory
        #[arg(long)]
        out: PathBuf,
    },
    /// Render one scene (TOML; fits/render/ holds the examples) with the truth and every
    /// method of its set: DIR/<name>.md (error ± s.e., ꟻLIP, flicker; no wall clock), DIR/<name>.json
    /// and the PNG grid (and frame strip for a camera path).
    ///
    /// Renders one scene (examples: `fits/render/*.toml`) on the CPU: the truth (every
    /// texel the pixel covers shaded with its own f64 lobe and weighted by its exact
    /// coverage, quad lights and SG environments by MIS on scrambled Sobol points, two
    /// replicates for each pixel's standard error) and every method of the scene's set
    /// (`methods = "multiscale"`: the seed 000 mip filters through the shipped LTC table;
    /// `"specular-aa"`: the seed 003 and engine kernels; `"glints"`: under a quad light
    /// seed 002's brute-force P-NDF, CP range queries at three ranks and a plain mip, under
    /// an SG environment the CP point and prefiltered (Eq 8–9) queries at three ranks and a
    /// plain mip; `"truth-only"`), each
    /// through the shipped f32 code. Writes DIR/<name>.md (MSE and relative MSE, unbiased
    /// against the exact image, each ± the s.e. the truth's noise leaves; mean ꟻLIP; the
    /// truth's noise floor; flicker along a camera path),
    /// DIR/<name>.json and DIR/<name>-grid.png (truth first, each method's ꟻLIP map under
    /// it, columns and rows named in the picture; DIR/<name>-strip.png for a path). Scene keys: `[camera]` position, look_at, up,
    /// fov_deg, width, height (even, ≤ 2048), `path = { to, frames }`; `[surface]` kind
    /// (plane|sphere|torus), radius, minor_radius, repeats; `[material]` lobe
    /// (ggx|gaussian|ltc), alpha, sigma_r, normal_map (a generator, `flat` or a PNG path
    /// relative to the scene), normal_scale, map_size, map_seed; `[[lights]]` kind =
    /// point|quad|directional|environment|sg (`lobes = [{ axis, lambda, amplitude }, …]`,
    /// glints and truth-only only); `[render]` methods, truth_samples, seed, scales,
    /// exposure. Unknown keys, non-finite numbers, sizes beyond the limits (≤ 2^36 truth
    /// samples in all) and a point light on the surface are errors naming the key, exit 2,
    /// nothing written. `--preset` sets
    /// the glint set's P-NDF grid and CP iterations, as fits/render.toml gives them to the
    /// render study (the spec this build compiled in).
    Render {
        /// scene file (TOML)
        file: PathBuf,
        /// output directory
        #[arg(long)]
        out: PathBuf,
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
    },
    /// The horizon-map study of results/visibility.md on a height map: a square,
    /// power-of-two grey PNG (8/16-bit, ≤ 4096²), heights = value × SCALE texels. Writes
    /// DIR/horizon.md (every method's error against the exact visible fractions) and
    /// DIR/horizon.json.
    ///
    /// The horizon-map study of `results/visibility.md` on your height map (square,
    /// power-of-two grey PNG, 8/16-bit, ≤ 4096²; heights = grey value × S texels, S ∈ (0,
    /// 1e6], default 16): Fournier's ramp, Tan et al.'s erf HDF, the Legendre series and
    /// the joint forms (product, Eq 28, Ashikhmin) against the exact visible fractions of
    /// the map's footprints, at the levels and footprint counts fits/visibility.toml sets
    /// for the preset (as this build compiled it in). Writes DIR/horizon.md and DIR/horizon.json; bad input (NaN or
    /// out-of-range scale, non-square or broken PNG) exits 2 with one line and writes
    /// nothing.
    Horizon {
        #[arg(long)]
        input: PathBuf,
        /// texels of height per unit of grey value (0, 1e6]
        #[arg(long, default_value_t = 16.0)]
        scale: f64,
        #[arg(long)]
        out: PathBuf,
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
    },
    /// Judge the engines' renders of the engine-check scenes against the truth, the table's
    /// and the shader's shares apart: three.js (engines/three: `node render.mjs --table
    /// shipped|ours|compact --out FILE`) and Bevy (engines/bevy-check: `cargo run -- --table
    /// bevy|ours …`); each engine given as both runs or not at all (three.js's compact
    /// drop-in run optional, judged with results/fits/ltc-compact.json); writes
    /// DIR/engines.{md,json,svg}
    Engines {
        /// three.js's run with its own table
        #[arg(long, requires = "three_ours")]
        three_shipped: Option<PathBuf>,
        /// three.js's run with ours
        #[arg(long, requires = "three_shipped")]
        three_ours: Option<PathBuf>,
        /// three.js's run with the compact drop-in (RectAreaLightTexturesLib.compact.js)
        #[arg(long, requires = "three_shipped")]
        three_compact: Option<PathBuf>,
        /// three.js's RectAreaLightTexturesLib.js (the shipped table's numbers)
        #[arg(long, default_value = "target/shipped/RectAreaLightTexturesLib.js")]
        shipped: PathBuf,
        /// Bevy's run with its embedded table
        #[arg(long, requires = "bevy_ours")]
        bevy_shipped: Option<PathBuf>,
        /// Bevy's run with ours through AreaLightLuts
        #[arg(long, requires = "bevy_shipped")]
        bevy_ours: Option<PathBuf>,
        /// Bevy's embedded ltc.ktx2 (bevy_pbr 0.19.1's src/ltc/ltc.ktx2)
        #[arg(long, default_value = "target/shipped/bevy_ltc.ktx2")]
        bevy_table: PathBuf,
        /// the scenes the harnesses rendered
        #[arg(long, default_value = "engines/three/scenes.json")]
        scenes: PathBuf,
        /// output directory
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Judge three.js's sheen runs (engines/three: `node render.mjs --table sheen --scenes
    /// FILE --out RUN`: the sheen alone, as three is and with
    /// results/textures/three/RectAreaLightSheen.js) against the truth, each on the scene
    /// file it names; writes DIR/engines-sheen.{md,json}
    EnginesSheen {
        /// a harness sheen run (repeat for each scene file)
        #[arg(long, required = true)]
        three: Vec<PathBuf>,
        /// output directory
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Compare our GGX LTC table (results/fits/ltc-ggx.json) with a shipped one read from
    /// FILE (selfshadow ltc.js or three.js RectAreaLightTexturesLib.js); writes
    /// DIR/ltc-compare.md. The file is only read.
    ///
    /// Compares our GGX LTC table (`results/fits/ltc-ggx.json`, from `regen --only
    /// ltc-ggx`) with a shipped one read from FILE — selfshadow/ltc_code
    /// `fit/results/ltc.js` (`--mat g_ltc_1 --mag g_ltc_2`), three.js
    /// `RectAreaLightTexturesLib.js` (arrays `LTC_MAT_1`/`LTC_MAT_2`, the default; `npm
    /// pack three@0.187.0`, as `.ci/run` does into target/shipped/) or our own
    /// `results/textures/ltc_ggx.js` — as a shader samples them: each table with its own
    /// norm, stored in f32 and in f16, every cell and every square (both textures
    /// interpolated bilinearly at its centre), per row and per column, the worst cells,
    /// heat maps; writes DIR/ltc-compare.{md,json,svg} and ltc-compare-rows.svg, which
    /// `regen --only ltc-ggx` summarises in results/ltc-ggx.md. `--norm-ours`
    /// uses our quadrature norms for both tables (only the matrices are compared; the file
    /// then needs only the matrix array); cells given as NaN are skipped, so a partial
    /// table works; `--source` records where the file came from. The file is only read,
    /// never copied.
    LtcCompare {
        /// the shipped table (JS or JSON text with the two arrays)
        #[arg(long)]
        shipped: PathBuf,
        /// name of the M⁻¹ array
        #[arg(long, default_value = "LTC_MAT_1")]
        mat: String,
        /// name of the (norm, fresnel) array
        #[arg(long, default_value = "LTC_MAT_2")]
        mag: String,
        /// use our norms (the BRDF albedo by quadrature) for both tables: compares the
        /// fitted matrices only, and the file needs only the M⁻¹ array
        #[arg(long)]
        norm_ours: bool,
        /// where the file came from (recorded in the report)
        #[arg(long)]
        source: Option<String>,
        /// Bevy's embedded table (bevy_pbr's src/ltc/ltc.ktx2): adds Bevy's path
        #[arg(long)]
        bevy: Option<PathBuf>,
        /// output directory
        #[arg(long, default_value = "results")]
        out: PathBuf,
    },
    /// Our CP-ALS against TensorLy's parafac on the same P-NDF tensors; needs
    /// python3 with numpy and tensorly; writes results/tensor-tensorly.json (rendered into
    /// results/tensor.md by `regen --only tensor`).
    ///
    /// Our CP-ALS and TensorLy's `parafac` on the same P-NDF tensors from the same start,
    /// rank, tolerance and stop rule, one core each; writes `results/tensor-tensorly.json`,
    /// which `regen --only tensor` renders into `results/tensor.md`. Needs `pip install
    /// numpy tensorly`; without them it says so (exit 2) and writes nothing.
    TensorlyCompare {
        /// the Python interpreter
        #[arg(long, default_value = "python3")]
        python: String,
        #[arg(long, value_enum, default_value_t = Preset::Default)]
        preset: Preset,
    },
    /// Write the CLI reference (every subcommand's --help) to a markdown file.
    #[command(hide = true)]
    CliReference {
        /// where to write it
        #[arg(long, default_value = "docs/cli.md")]
        out: PathBuf,
    },
    /// Write results/README.md: every output of results/, the command that writes it and
    /// what it reads (from the index in src/results/index.rs).
    #[command(hide = true)]
    ResultsReadme,
    /// Turn criterion output (target/criterion) into results/performance.md.
    ///
    /// Reads criterion's output (default `target/criterion`) and writes
    /// `results/performance.md` (time per configuration next to the error it reaches; the
    /// SIMD kernels' pixels/s, ratios and errors; the filters' cost next to accuracy) and
    /// `results/costs.json` (what `scene` chooses from). Run `cargo bench --bench engines`
    /// and `cargo bench --bench deliverables` (shader translation and validation per
    /// module, the prefilter tool at 2048²) first (`cargo bench --bench engines -- kernel-`
    /// for the kernels only). `--main-job-only` replaces only the main job's wall-clock
    /// section of an existing `results/performance.md` from
    /// `target/main-job-{cold,warm}.json` (the criterion tables stay as measured);
    /// `--compact-only` its compact LTC tables' section and results/ltc-compact-cost.svg,
    /// from criterion's `ltc-compact` group and results/fits/ltc-compact.json;
    /// `--ltc-fit-only` its LTC fitting and polygon section, from criterion's `ltc-fit-*`
    /// and `ltc-polygon` groups.
    BenchReport {
        /// criterion output directory
        #[arg(long, default_value = "target/criterion")]
        criterion: PathBuf,
        /// refresh only the main job's wall-clock section (no benches needed)
        #[arg(long, conflicts_with_all = ["compact_only", "ltc_fit_only"])]
        main_job_only: bool,
        /// refresh only the compact LTC tables' section and its plot, from criterion's
        /// ltc-compact group (`cargo bench --bench deliverables -- ltc-compact`)
        #[arg(long, conflicts_with = "ltc_fit_only")]
        compact_only: bool,
        /// refresh only the LTC fitting and polygon section, from criterion's
        /// ltc-fit-cell, ltc-fit-column and ltc-polygon groups (`cargo bench --bench
        /// engines -- ltc-`)
        #[arg(long)]
        ltc_fit_only: bool,
    },
}

/// The CLI reference (docs/cli.md): the long help of the program and of every subcommand,
/// at a fixed width, so the file is the same on every machine.
pub fn reference() -> String {
    use clap::CommandFactory;
    let mut root = Cli::command().term_width(100);
    root.build();
    let mut md = String::from(
        "<!-- @generated by `cargo run --release -- cli-reference` from the help texts in src/cli/; do not edit. -->\n\
         # CLI reference\n\nThe `--help` of `ndfbench` and of each subcommand, as the program prints them.\n\n",
    );
    let block = |c: &mut clap::Command| {
        format!(
            "```text\n{}\n```\n",
            c.render_long_help().to_string().trim_end()
        )
    };
    md.push_str(&block(&mut root));
    let names: Vec<String> = root
        .get_subcommands()
        .filter(|c| !c.is_hide_set() && c.get_name() != "help")
        .map(|c| c.get_name().to_string())
        .collect();
    for name in names {
        if let Some(c) = root.find_subcommand_mut(&name) {
            md.push_str(&format!("\n## `ndfbench {name}`\n\n{}", block(c)));
        }
    }
    md
}
