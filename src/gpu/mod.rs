//! A GPU path for the embarrassingly parallel truths: the P-NDF brute force (seed 002
//! Eq 2) as a wgpu compute shader (`pndf.wgsl`, one invocation per footprint × bin) and
//! the filters' footprint truth (seed 004 Eq 11, `truth.wgsl`, one invocation per view ×
//! light pair), f32 throughout. Their f64 references are
//! [`crate::tensor::pndf::pndf_image`] and [`crate::filters::truth::Truth::value`];
//! tests/gpu.rs bounds the differences on whatever adapter is present (lavapipe in CI).
//! Without an adapter [`Gpu::new`] says why and the callers stay on the CPU.

use crate::error::{Error, Result};
use crate::filters::footprint::NormalMap;

/// The shader's text (validated by naga in tests/gpu.rs before any adapter is asked).
pub const PNDF_WGSL: &str = include_str!("pndf.wgsl");

/// The footprint-truth shader's text.
pub const TRUTH_WGSL: &str = include_str!("truth.wgsl");

/// Invocations per dispatch at most (wgpu's 65 535 workgroups of 64 in x).
const MAX_INVOCATIONS: usize = 65_535 * 64;

/// One adapter and its device.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// wgpu's high-performance adapter (a hardware GPU where there is one; `WGPU_BACKEND`
    /// restricts the choice), or the reason there is none.
    pub fn new() -> std::result::Result<Gpu, String> {
        pollster::block_on(async {
            let instance = wgpu::Instance::new(
                wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
            );
            let adapter = instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    ..Default::default()
                })
                .await
                .map_err(|e| format!("no wgpu adapter ({e})"))?;
            let info = adapter.get_info();
            let (device, queue) = adapter
                .request_device(&wgpu::DeviceDescriptor::default())
                .await
                .map_err(|e| format!("no device on {} ({e})", info.name))?;
            Ok(Gpu {
                device,
                queue,
                info,
            })
        })
    }

    /// The P-NDF images (row-major, res², per unit projected area) of the footprints
    /// centred at `centres` with σ_P and σ_r: the f32 twin of
    /// [`crate::tensor::pndf::pndf_image`] for each centre.
    pub fn pndf_images(
        &self,
        map: &NormalMap,
        centres: &[(f64, f64)],
        sigma_p: f64,
        sigma_r: f64,
        res: usize,
    ) -> Result<Vec<Vec<f32>>> {
        // one footprint's bins must fit one dispatch, and its texel loop stay bounded
        if !(sigma_p > 0.0 && sigma_p <= 1024.0 && sigma_r > 0.0 && (2..=1024).contains(&res)) {
            return Err(Error::InvalidArgument(format!(
                "GPU P-NDF needs 0 < σ_P ≤ 1024, σ_r > 0 and 2 ≤ res ≤ 1024 (got {sigma_p:e}, {sigma_r:e}, {res})"
            )));
        }
        let bins = res * res;
        let per = (MAX_INVOCATIONS / bins).max(1);
        let normals: Vec<[f32; 2]> = map
            .normals
            .iter()
            .map(|n| [n.x as f32, n.y as f32])
            .collect();
        let c: Vec<[f32; 2]> = centres.iter().map(|&(x, y)| [x as f32, y as f32]).collect();
        let d = &self.device;
        use wgpu::util::DeviceExt;
        let storage = |bytes: &[u8]| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let nb = storage(bytemuck_pairs(&normals).as_slice());
        let cb = storage(bytemuck_pairs(&c).as_slice());
        let pipeline = self.pipeline(PNDF_WGSL, "ndfb_pndf_main");
        let rad = (4.0 * sigma_p).ceil() as i32;
        let mut out = Vec::with_capacity(centres.len());
        for first in (0..centres.len()).step_by(per) {
            let count = per.min(centres.len() - first);
            let words: [u32; 8] = [
                map.width as u32,
                map.height as u32,
                res as u32,
                rad as u32,
                count as u32,
                (sigma_p as f32).to_bits(),
                (sigma_r as f32).to_bits(),
                first as u32,
            ];
            let pb = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: &words
                    .iter()
                    .flat_map(|w| w.to_le_bytes())
                    .collect::<Vec<u8>>(),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let vals = self.run(&pipeline, [&nb, &cb, &pb], count * bins)?;
            out.extend(vals.chunks(bins).map(<[f32]>::to_vec));
        }
        Ok(out)
    }

    /// The footprint-averaged GGX lobe ρ_A(l, v)(n·l) of the texel normals `normals`
    /// (unit) with weights `weights` (summing to 1) and base roughness α, for each
    /// (v, l) pair: the f32 twin of [`crate::filters::truth::Truth::value`] (isotropic
    /// GGX).
    pub fn footprint_truth(
        &self,
        normals: &[[f64; 3]],
        weights: &[f64],
        alpha: f64,
        pairs: &[([f64; 3], [f64; 3])],
    ) -> Result<Vec<f32>> {
        if normals.len() != weights.len() || !(alpha > 0.0 && alpha <= 1.0) || pairs.is_empty() {
            return Err(Error::InvalidArgument(format!(
                "GPU footprint truth needs one weight per normal, 0 < α ≤ 1 and at least one pair (got {} normals, {} weights, α = {alpha:e}, {} pairs)",
                normals.len(), weights.len(), pairs.len()
            )));
        }
        if pairs.len() > MAX_INVOCATIONS {
            return Err(Error::InvalidArgument(format!(
                "GPU footprint truth: {} pairs exceed one dispatch ({MAX_INVOCATIONS})",
                pairs.len()
            )));
        }
        let f = |x: f64| (x as f32).to_le_bytes();
        let texels: Vec<u8> = normals
            .iter()
            .zip(weights)
            .flat_map(|(n, &w)| [n[0], n[1], n[2], w].into_iter().flat_map(f))
            .collect();
        let dirs: Vec<u8> = pairs
            .iter()
            .flat_map(|(v, l)| {
                [v[0], v[1], v[2], 0.0, l[0], l[1], l[2], 0.0]
                    .into_iter()
                    .flat_map(f)
            })
            .collect();
        let d = &self.device;
        use wgpu::util::DeviceExt;
        let init = |bytes: &[u8], usage| {
            d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: None,
                contents: bytes,
                usage,
            })
        };
        let params: Vec<u8> = [
            normals.len() as u32,
            pairs.len() as u32,
            (alpha as f32).to_bits(),
            0,
        ]
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .collect();
        let (tb, pb) = (
            init(&texels, wgpu::BufferUsages::STORAGE),
            init(&dirs, wgpu::BufferUsages::STORAGE),
        );
        let ub = init(&params, wgpu::BufferUsages::UNIFORM);
        let pipeline = self.pipeline(TRUTH_WGSL, "ndfb_truth_main");
        self.run(&pipeline, [&tb, &pb, &ub], pairs.len())
    }

    /// The compute pipeline of `entry` in the WGSL text `wgsl`.
    fn pipeline(&self, wgsl: &str, entry: &str) -> wgpu::ComputePipeline {
        let module = self
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
        self.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: None,
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
    }

    fn run(
        &self,
        pipeline: &wgpu::ComputePipeline,
        inputs: [&wgpu::Buffer; 3],
        n: usize,
    ) -> Result<Vec<f32>> {
        let d = &self.device;
        let size = (n * 4) as u64;
        let buf = |usage| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let outb = buf(wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC);
        let read = buf(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        let mut entries: Vec<wgpu::BindGroupEntry> = inputs
            .iter()
            .enumerate()
            .map(|(k, b)| wgpu::BindGroupEntry {
                binding: k as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 3,
            resource: outb.as_entire_binding(),
        });
        let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups(n.div_ceil(64) as u32, 1, 1);
        }
        enc.copy_buffer_to_buffer(&outb, 0, &read, 0, size);
        self.queue.submit([enc.finish()]);
        let slice = read.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        let lost =
            |e: String| Error::InvalidArgument(format!("GPU P-NDF on {}: {e}", self.info.name));
        d.poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| lost(e.to_string()))?;
        let data = slice
            .get_mapped_range()
            .map_err(|e| lost(format!("{e:?}")))?;
        Ok(data
            .chunks(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect())
    }
}

impl Gpu {
    /// Run a compute entry `entry` of `wgsl` that writes two `rgba16float` storage
    /// textures of side `n` (bindings 0 and 1 of group 0; workgroups of 8×8, as the
    /// generated compact LTC rebuild, results/wgsl/ltc_compact.wgsl) and read both back:
    /// per texel the four binary16 bit patterns of each. A typed error (naming the
    /// adapter and containing "refused") where the adapter rejects the pipeline.
    pub fn fill_two_rgba16f(
        &self,
        wgsl: &str,
        entry: &str,
        n: usize,
    ) -> Result<[Vec<[u16; 4]>; 2]> {
        if !(2..=4096).contains(&n) {
            return Err(Error::InvalidArgument(format!(
                "GPU texture fill: side {n} (2..=4096)"
            )));
        }
        let d = &self.device;
        let size = wgpu::Extent3d {
            width: n as u32,
            height: n as u32,
            depth_or_array_layers: 1,
        };
        let tex = || {
            d.create_texture(&wgpu::TextureDescriptor {
                label: None,
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        // an adapter without rgba16float storage (a downlevel GL) refuses here: a typed
        // error naming it, not wgpu's panic
        let scope = d.push_error_scope(wgpu::ErrorFilter::Validation);
        let (t1, t2) = (tex(), tex());
        let (v1, v2) = (
            t1.create_view(&wgpu::TextureViewDescriptor::default()),
            t2.create_view(&wgpu::TextureViewDescriptor::default()),
        );
        let pipeline = self.pipeline(wgsl, entry);
        let bg = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&v1),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&v2),
                },
            ],
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::InvalidArgument(format!(
                "GPU texture fill: {} refused the rgba16float storage pipeline: {e}",
                self.info.name
            )));
        }
        let row = (n * 8).div_ceil(256) * 256;
        let read = |_: usize| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: (row * n) as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let (r1, r2) = (read(0), read(1));
        let mut enc = d.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bg, &[]);
            let g = n.div_ceil(8) as u32;
            pass.dispatch_workgroups(g, g, 1);
        }
        for (t, b) in [(&t1, &r1), (&t2, &r2)] {
            enc.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: t,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: b,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row as u32),
                        rows_per_image: Some(n as u32),
                    },
                },
                size,
            );
        }
        self.queue.submit([enc.finish()]);
        let lost = |e: String| {
            Error::InvalidArgument(format!("GPU texture fill on {}: {e}", self.info.name))
        };
        let mut out = [Vec::new(), Vec::new()];
        for (o, b) in out.iter_mut().zip([&r1, &r2]) {
            let slice = b.slice(..);
            slice.map_async(wgpu::MapMode::Read, |_| {});
            d.poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| lost(e.to_string()))?;
            let data = slice
                .get_mapped_range()
                .map_err(|e| lost(format!("{e:?}")))?;
            for j in 0..n {
                for i in 0..n {
                    let k = j * row + i * 8;
                    o.push(std::array::from_fn(|c| {
                        u16::from_le_bytes([data[k + 2 * c], data[k + 2 * c + 1]])
                    }));
                }
            }
        }
        Ok(out)
    }
}

/// Little-endian bytes of f32 pairs.
fn bytemuck_pairs(v: &[[f32; 2]]) -> Vec<u8> {
    v.iter()
        .flat_map(|p| p.iter().flat_map(|x| x.to_le_bytes()))
        .collect()
}
