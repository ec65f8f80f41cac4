//! The engine files of the GGX LTC table (results/textures/) read back by independent
//! readers — the `ktx2` and `ddsfile` crates, a byte-level reading of the raw files
//! against the JSON manifest, the shipped-table parser for the ES module — texel by
//! texel against results/fits/ltc-ggx.json: bit-exact for f32, and for f16 exactly the
//! stored binary16 table, which is within half an ulp of the f64 table for norm and
//! fresnel and within the storage search's 4 binary16 steps for a, b, c, d. Also:
//! the files are fresh, and the second texture means what three.js and Bevy assume.

use half::f16;
use ndfbench::codegen::textures;
use ndfbench::ltc::table::FittedTable;
use std::path::Path;

fn table() -> FittedTable {
    ndfbench::results::ltc::table(Path::new("results"), "ltc-ggx")
        .expect("results/fits/ltc-ggx.json")
}

fn read(name: &str) -> Vec<u8> {
    let p = Path::new("results").join(textures::DIR).join(name);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Position of a binary16 number on the line of all of them (−0 and +0 both 0).
fn ordinal(h: f16) -> i32 {
    let b = h.to_bits() as i32;
    if b & 0x8000 != 0 {
        -(b & 0x7fff)
    } else {
        b
    }
}

/// How many binary16 steps `h` is from `x` rounded to nearest; with `half` also whether
/// `h` is within half an ulp of `x` (i.e. is its rounding).
fn steps(h: f16, x: f64) -> i32 {
    (ordinal(h) - ordinal(f16::from_f64(x))).abs()
}

/// Every decoded f16 texel of `layer` equals the stored table, and the stored table is
/// within its stated distance of the f64 table.
fn check_f16_texels(t: &FittedTable, layer: usize, texels: &[f16]) {
    assert_eq!(texels.len(), 4 * t.n * t.n);
    for k in 0..t.n * t.n {
        let h = t.half_cell(k);
        for c in 0..4 {
            let got = texels[4 * k + c];
            // the matrix entries: up to 4 steps from nearest (the storage search), or
            // where rounding to nearest mirrors the lobe (det M⁻¹ = ad − bc ≤ 0, or b
            // across zero) up to 64 more (b toward 0, d up until it keeps it); norm and
            // fresnel: their rounding to nearest, i.e. within half an ulp
            let e = &t.cells[k];
            let near: Vec<f64> = (0..4).map(|q| f16::from_f64(e[q]).to_f64()).collect();
            let mirrored = !(near[0] * near[3] - near[1] * near[2] > 0.0 && near[1] * e[1] >= 0.0);
            let (want, full, bound) = if layer == 0 {
                (h[c], t.cells[k][c], if mirrored { 68 } else { 4 })
            } else if c < 2 {
                (h[4 + c], t.cells[k][4 + c], 0)
            } else {
                (f16::ZERO, 0.0, 0)
            };
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "texel {k} channel {c} of layer {layer}"
            );
            assert!(
                steps(got, full) <= bound,
                "texel {k} channel {c}: {got} is {} f16 steps from {full}",
                steps(got, full)
            );
        }
    }
}

fn f16s(bytes: &[u8]) -> Vec<f16> {
    bytes
        .chunks_exact(2)
        .map(|b| f16::from_bits(u16::from_le_bytes([b[0], b[1]])))
        .collect()
}

#[test]
fn engine_files_are_fresh() {
    for kind in &textures::TABLES {
        let t = ndfbench::results::ltc::table(Path::new("results"), kind.fit)
            .unwrap_or_else(|e| panic!("results/fits/{}.json: {e}", kind.fit));
        for (rel, bytes) in textures::render(&t, kind, ndfbench::codegen::COMMAND) {
            let p = Path::new("results").join(&rel);
            let on_disk = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(
                on_disk == bytes,
                "{} is stale with respect to results/fits/{}.json: run `{}`",
                p.display(),
                kind.fit,
                ndfbench::codegen::COMMAND
            );
        }
    }
}

/// Every table's KTX2 reads back with the `ktx2` crate as 64×64×2 R16G16B16A16_SFLOAT
/// holding exactly its stored binary16 table (layer 0 = a, b, c, d; layer 1 = norm,
/// fresnel, 0, 0).
#[test]
fn every_tables_ktx2_holds_its_stored_binary16_table() {
    for kind in &textures::TABLES {
        let t = ndfbench::results::ltc::table(Path::new("results"), kind.fit).unwrap();
        let bytes = read(&format!("{}.ktx2", kind.stem));
        let r = ktx2::Reader::new(&bytes[..]).expect("a valid KTX2 file");
        let h = r.header();
        assert_eq!(
            h.format,
            Some(ktx2::Format::R16G16B16A16_SFLOAT),
            "{}",
            kind.stem
        );
        assert_eq!(
            (h.pixel_width as usize, h.layer_count),
            (t.n, 2),
            "{}",
            kind.stem
        );
        let level = r.levels().next().expect("one level");
        let v = f16s(level.data);
        let nn = t.n * t.n;
        assert_eq!(v.len(), 2 * nn * 4, "{}", kind.stem);
        for k in 0..nn {
            let c = t.half_cell(k);
            let want = [c[0], c[1], c[2], c[3], c[4], c[5], f16::ZERO, f16::ZERO];
            for (q, w) in want.iter().enumerate() {
                let got = v[(q / 4) * nn * 4 + k * 4 + q % 4];
                assert_eq!(
                    got.to_bits(),
                    w.to_bits(),
                    "{} texel {k} value {q}",
                    kind.stem
                );
            }
        }
    }
}

#[test]
fn ktx2_reads_back_with_the_ktx2_crate_in_bevys_layout() {
    let t = table();
    let bytes = read("ltc_ggx.ktx2");
    let r = ktx2::Reader::new(&bytes[..]).expect("a valid KTX2 file");
    let h = r.header();
    assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
    assert_eq!(h.type_size, 2);
    assert_eq!((h.pixel_width, h.pixel_height, h.pixel_depth), (64, 64, 0));
    assert_eq!(t.n, 64);
    assert_eq!((h.layer_count, h.face_count, h.level_count), (2, 1, 1));
    assert!(h.supercompression_scheme.is_none());
    // the descriptor matches the one the crate derives from the format
    let dfd = r.basic_dfd().expect("a basic data-format descriptor");
    let (want, _) = ktx2::dfd::Basic::from_format(ktx2::Format::R16G16B16A16_SFLOAT).unwrap();
    assert_eq!(dfd.color_model, want.color_model);
    assert_eq!(dfd.bytes_planes, want.bytes_planes);
    assert_eq!(dfd.sample_information, want.sample_information);
    let levels: Vec<_> = r.levels().collect();
    assert_eq!(levels.len(), 1);
    let data = levels[0].data;
    let layer = 64 * 64 * 8;
    assert_eq!(data.len(), 2 * layer);
    check_f16_texels(&t, 0, &f16s(&data[..layer]));
    check_f16_texels(&t, 1, &f16s(&data[layer..]));
}

/// The zstd-supercompressed KTX2 (as Bevy ships its own table): the `ktx2` crate reads
/// its header and level index, zstd gives back exactly the uncompressed file's level, and
/// its header and descriptor agree with Bevy's embedded `ltc.ktx2` field by field where
/// that file is at hand (.ci/run fetches it; the comparison skips without it).
#[test]
fn zstd_ktx2_is_the_same_table_in_bevys_own_encoding() {
    let t = table();
    let bytes = read("ltc_ggx_zstd.ktx2");
    let r = ktx2::Reader::new(&bytes[..]).expect("a valid KTX2 file");
    let h = r.header();
    assert_eq!(
        h.supercompression_scheme,
        Some(ktx2::SupercompressionScheme::Zstandard)
    );
    assert_eq!(h.format, Some(ktx2::Format::R16G16B16A16_SFLOAT));
    assert_eq!((h.layer_count, h.face_count, h.level_count), (2, 1, 1));
    let level = r.levels().next().expect("one level");
    assert_eq!(level.uncompressed_byte_length, 2 * 64 * 64 * 8);
    let data = zstd::bulk::decompress(level.data, 2 * 64 * 64 * 8).expect("zstd");
    let plain = read("ltc_ggx.ktx2");
    let plain_level = ktx2::Reader::new(&plain[..])
        .unwrap()
        .levels()
        .next()
        .unwrap()
        .data
        .to_vec();
    assert_eq!(data, plain_level);
    let layer = 64 * 64 * 8;
    check_f16_texels(&t, 0, &f16s(&data[..layer]));
    check_f16_texels(&t, 1, &f16s(&data[layer..]));
    assert_eq!(r.basic_dfd().expect("a descriptor").bytes_planes[0], 8);
    let bevy = Path::new("target/shipped/bevy_ltc.ktx2");
    match std::fs::read(bevy) {
        Ok(b) => {
            let rb = ktx2::Reader::new(&b[..]).expect("Bevy's file");
            let hb = rb.header();
            assert_eq!(
                (
                    h.format,
                    h.type_size,
                    h.pixel_width,
                    h.pixel_height,
                    h.pixel_depth
                ),
                (
                    hb.format,
                    hb.type_size,
                    hb.pixel_width,
                    hb.pixel_height,
                    hb.pixel_depth
                )
            );
            assert_eq!(
                (
                    h.layer_count,
                    h.face_count,
                    h.level_count,
                    h.supercompression_scheme
                ),
                (
                    hb.layer_count,
                    hb.face_count,
                    hb.level_count,
                    hb.supercompression_scheme
                )
            );
            let (d, db) = (r.basic_dfd().unwrap(), rb.basic_dfd().unwrap());
            assert_eq!(d.color_model, db.color_model);
            assert_eq!(d.bytes_planes, db.bytes_planes);
            assert_eq!(d.sample_information, db.sample_information);
            let lb = rb.levels().next().unwrap();
            assert_eq!(level.uncompressed_byte_length, lb.uncompressed_byte_length);
        }
        Err(_) => eprintln!(
            "skipped the comparison with Bevy's file: {} absent (.ci/run fetches it)",
            bevy.display()
        ),
    }
}

#[test]
fn dds_reads_back_with_the_ddsfile_crate() {
    let t = table();
    for layer in 0..2 {
        let bytes = read(&format!("ltc_ggx_{}.dds", layer + 1));
        let d = ddsfile::Dds::read(&bytes[..]).expect("a valid DDS file");
        assert_eq!(
            d.get_dxgi_format(),
            Some(ddsfile::DxgiFormat::R16G16B16A16_Float)
        );
        assert_eq!((d.get_width(), d.get_height()), (64, 64));
        assert_eq!(d.get_num_array_layers(), 1);
        check_f16_texels(&t, layer, &f16s(d.get_data(0).unwrap()));
    }
}

#[test]
fn raw_files_match_their_manifest_and_the_table() {
    let t = table();
    let m: serde_json::Value = serde_json::from_slice(&read("ltc_ggx.json")).unwrap();
    assert_eq!(m["width"], 64);
    assert_eq!(m["byte_order"], "little-endian");
    for (layer, tex) in m["textures"].as_array().unwrap().iter().enumerate() {
        let h = f16s(&read(tex["f16"].as_str().unwrap()));
        check_f16_texels(&t, layer, &h);
        let f: Vec<f32> = read(tex["f32"].as_str().unwrap())
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        assert_eq!(f.len(), 4 * 64 * 64);
        for k in 0..t.n * t.n {
            let c = &t.cells[k];
            let want = if layer == 0 {
                [c[0], c[1], c[2], c[3]]
            } else {
                [c[4], c[5], 0.0, 0.0]
            };
            for ch in 0..4 {
                assert_eq!(
                    f[4 * k + ch].to_bits(),
                    (want[ch] as f32).to_bits(),
                    "f32 texel {k} channel {ch} of layer {layer}"
                );
            }
        }
    }
}

#[test]
fn es_module_round_trips_through_the_shipped_table_reader() {
    let t = table();
    let text = String::from_utf8(read("ltc_ggx.js")).unwrap();
    let shipped =
        ndfbench::ltc::compare::Shipped::parse(&text, "LTC_MAT_1", "LTC_MAT_2").expect("parses");
    assert_eq!(shipped.n, t.n);
    for k in 0..t.n * t.n {
        let c = &t.cells[k];
        for ch in 0..4 {
            assert_eq!(
                (shipped.mat[k][ch] as f32).to_bits(),
                (c[ch] as f32).to_bits()
            );
        }
        for ch in 0..2 {
            assert_eq!(
                (shipped.mag[k][ch] as f32).to_bits(),
                (c[4 + ch] as f32).to_bits()
            );
        }
    }
}

/// ∫ f·F_Schlick(F0) dl for each F0 by VNDF importance sampling of the GGX BRDF
/// (height-correlated G2) with `n` independent uniform samples (ChaCha8, fixed seed): an
/// estimator independent of the table's half-vector quadrature; (mean, s.e.) per F0. A
/// deterministic midpoint grid in u would not do: GGX's tail below the horizon
/// (probability ~α² at normal incidence) falls into its last row all or nothing.
fn schlick_weighted(alpha: f64, theta: f64, f0s: &[f64], n: usize) -> Vec<(f64, f64)> {
    use ndfbench::integrate::mc::Strategy;
    use ndfbench::microfacet::sampling::VndfSampler;
    use ndfbench::microfacet::{Microsurface, Roughness};
    use rand::{Rng, SeedableRng};
    let s = Microsurface::ggx(Roughness::iso(alpha).unwrap());
    let v = nalgebra::Vector3::new(theta.sin(), 0.0, theta.cos());
    let vndf = VndfSampler::new(s, v).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let (mut sum, mut sum2) = (vec![0.0; f0s.len()], vec![0.0; f0s.len()]);
    for _ in 0..n {
        let u = [rng.random::<f64>(), rng.random::<f64>()];
        let Some(h) = vndf.sample(u) else { continue };
        let l = h * (2.0 * v.dot(&h)) - v;
        if l.z <= 0.0 {
            continue;
        }
        // f·l_z / pdf(l) with pdf(l) = D·G1(v)·(v·h)/v_z / (4 v·h)
        let w = s.g2_correlated(&l, &v, &h) / s.g1_dir(&v);
        let s5 = (1.0 - v.dot(&h)).powi(5);
        for (k, f0) in f0s.iter().enumerate() {
            let x = w * (f0 + (1.0 - f0) * s5);
            sum[k] += x;
            sum2[k] += x * x;
        }
    }
    let m = n as f64;
    (0..f0s.len())
        .map(|k| {
            let mean = sum[k] / m;
            (mean, ((sum2[k] / m - mean * mean).max(0.0) / m).sqrt())
        })
        .collect()
}

#[test]
fn second_texture_weights_schlick_fresnel_as_engines_assume() {
    // three.js and Bevy: specular weight = F0·t2.x + (1 − F0)·t2.y
    let t = table();
    let n = t.n;
    for (i, j) in [(10, 5), (20, 30), (40, 50), (63, 60), (32, 63), (50, 10)] {
        let r = i as f64 / (n - 1) as f64;
        let tt = j as f64 / (n - 1) as f64;
        let (alpha, theta) = (r * r, (1.0 - tt * tt).acos().min(89.99f64.to_radians()));
        let c = t.cell(i, j);
        let f0s = [0.0, 0.04, 0.5, 1.0];
        for (f0, (mc, se)) in f0s
            .iter()
            .zip(schlick_weighted(alpha, theta, &f0s, 1 << 20))
        {
            let table_value = f0 * c[4] + (1.0 - f0) * c[5];
            // 5 s.e. of the MC, plus the table's own quadrature tolerance (1e-9)
            assert!(
                (table_value - mc).abs() <= 5.0 * se + 1e-8,
                "cell ({i}, {j}) F0 = {f0}: table {table_value}, MC {mc} ± {se}"
            );
        }
    }
}

#[test]
fn ltc_compare_reads_the_es_module_back_as_the_same_table() {
    // ltc-compare's reader (the one `--shipped` goes through, checked for comparability
    // as the command checks it) reads our ES module back as our table in f32, bit for bit
    use ndfbench::ltc::compare::Shipped;
    let text = std::fs::read_to_string("results/textures/ltc_ggx.js").unwrap();
    let js = Shipped::parse(&text, "LTC_MAT_1", "LTC_MAT_2").expect("parses");
    js.check_comparable("ltc_ggx.js").expect("comparable");
    let t = ndfbench::results::ltc::table(Path::new("results"), ndfbench::results::names::LTC_GGX)
        .unwrap();
    assert_eq!(js.n, t.n);
    for k in 0..t.n * t.n {
        let c = &t.cells[k];
        for q in 0..4 {
            assert_eq!(js.mat[k][q] as f32, c[q] as f32, "cell {k} entry {q}");
        }
        assert_eq!(
            js.mag[k].map(|x| x as f32),
            [c[4] as f32, c[5] as f32],
            "cell {k}"
        );
    }
}

/// Every texel of every f16 and f32 table written (the five isotropic tables' raw files,
/// which the KTX2, DDS and ES module hold bit for bit — see the tests above — and the
/// anisotropic table's raw binary16 texels) keeps its lobe: M⁻¹'s determinant is
/// positive (a negative one mirrors the lobe across the view plane) and b has the sign
/// of the f64 table's b (or is 0).
#[test]
fn every_stored_texel_keeps_its_lobe() {
    let mut checked = 0usize;
    let mut bad = Vec::new();
    for kind in ndfbench::codegen::textures::TABLES {
        let Ok(t) = ndfbench::results::ltc::table(Path::new("results"), kind.fit) else {
            continue;
        };
        let f16v: Vec<f64> = f16s(&read(&format!("{}_1_f16.bin", kind.stem)))
            .iter()
            .map(|h| h.to_f64())
            .collect();
        let f32v: Vec<f64> = read(&format!("{}_1_f32.bin", kind.stem))
            .chunks(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64)
            .collect();
        assert_eq!(f16v.len(), 4 * t.n * t.n);
        assert_eq!(f32v.len(), 4 * t.n * t.n);
        for k in 0..t.n * t.n {
            let b64 = t.cells[k][1];
            for (what, v) in [("f16", &f16v), ("f32", &f32v)] {
                let (a, b, c, d) = (v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]);
                checked += 1;
                if !(a * d - b * c > 0.0 && b * b64 >= 0.0) {
                    bad.push(format!(
                        "{} {what} texel ({}, {}): (a, b, c, d) = ({a:e}, {b:e}, {c:e}, {d:e}), f64 b = {b64:e}",
                        kind.stem,
                        k % t.n,
                        k / t.n
                    ));
                }
            }
        }
    }
    // the anisotropic table: layer 0 of each (r_y, φ) node is (a, b, c, d), layer 2 (e, g, h)
    if let Ok(at) = ndfbench::results::ltc_aniso::aniso_table(Path::new("results")) {
        let g = at.grid;
        let tex = f16s(&read("ltc_ggx_aniso_f16.bin"));
        let layer = g.n_r * g.n_t * 4;
        for kk in 0..g.n_phi {
            for iy in 0..g.n_r {
                let base = 3 * (kk * g.n_r + iy) * layer;
                for j in 0..g.n_t {
                    for ix in 0..g.n_r {
                        let at4 = |q: usize| -> Vec<f64> {
                            let o = base + q * layer + 4 * (ix + g.n_r * j);
                            tex[o..o + 4].iter().map(|h| h.to_f64()).collect()
                        };
                        let (m, x) = (at4(0), at4(2));
                        let p = [m[0], m[1], m[2], m[3], x[0], x[1], x[2]];
                        let det = ndfbench::ltc::aniso::inverse_of(&p).determinant();
                        let b64 = at.cells[g.index(ix, iy, kk, j)][1];
                        checked += 1;
                        if !(det > 0.0 && p[1] * b64 >= 0.0) {
                            bad.push(format!(
                                "ltc_ggx_aniso texel ({ix}, {iy}, {kk}, {j}): {p:?}, det {det:e}"
                            ));
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 0, "no table to check");
    assert!(
        bad.is_empty(),
        "{} of {checked} texels mirror their lobe:\n{}",
        bad.len(),
        bad.join("\n")
    );
}
