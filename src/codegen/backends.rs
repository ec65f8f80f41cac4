//! Every generated WGSL module through naga's four back ends (SPIR-V, MSL, HLSL, GLSL).
//!
//! A library module has no entry point, and three of the four back ends write only what
//! an entry point reaches, so each module is translated with a generated harness: one
//! compute entry point that calls every function of the module on arguments read from a
//! storage buffer and writes every result to another. The harness is the only place that
//! declares `@group`/`@binding` globals; the library modules never do.

use crate::error::{Error, Result};

/// A naga back end, with the target it is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Backend {
    Spv,
    Msl,
    Hlsl,
    Glsl,
}

/// The four back ends, in report order.
pub const BACKENDS: [Backend; 4] = [Backend::Spv, Backend::Msl, Backend::Hlsl, Backend::Glsl];

impl Backend {
    /// The target in words.
    pub fn target(self) -> &'static str {
        match self {
            Backend::Spv => "SPIR-V 1.0 (Vulkan)",
            Backend::Msl => "MSL 2.0 (Metal)",
            Backend::Hlsl => "HLSL SM 5.1 (D3D12)",
            Backend::Glsl => "GLSL 450 core (OpenGL, Godot)",
        }
    }
    /// Short name (table columns, file extensions).
    pub fn name(self) -> &'static str {
        match self {
            Backend::Spv => "spv",
            Backend::Msl => "msl",
            Backend::Hlsl => "hlsl",
            Backend::Glsl => "glsl",
        }
    }
}

/// What the shaders may use: naga's defaults plus `SHADER_FLOAT16_IN_FLOAT32`, which
/// the core WGSL built-in `unpack2x16float` of the binary16 LTC table needs (every WebGPU
/// implementation has it; GLSL ≥ 4.20 `unpackHalf2x16`, HLSL `f16tof32`, MSL `half2`).
pub const CAPABILITIES: naga::valid::Capabilities =
    naga::valid::Capabilities::SHADER_FLOAT16_IN_FLOAT32
        .union(naga::valid::Capabilities::MULTISAMPLED_SHADING)
        .union(naga::valid::Capabilities::CUBE_ARRAY_TEXTURES);

/// The entry point of the harness.
pub const ENTRY: &str = "ndfb_harness_main";

/// What the harness passes for one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arg {
    F32,
    U32,
    /// A `texture_2d_array<f32>` (the harness binds one at binding 2).
    TextureArray,
    /// A `sampler` (the harness binds one at binding 3).
    Sampler,
}

/// One function of a module as the harness calls it: its name, what each argument is,
/// and how many components its result has (a mat3x3 counts 9).
#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    pub name: String,
    pub args: Vec<Arg>,
    pub components: u32,
}

fn parse(src: &str, what: &str) -> Result<naga::Module> {
    naga::front::wgsl::parse_str(src).map_err(|e| {
        Error::InvalidArgument(format!("{what}: WGSL does not parse: {}", e.message()))
    })
}

fn validate(module: &naga::Module, what: &str) -> Result<naga::valid::ModuleInfo> {
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), CAPABILITIES)
        .validate(module)
        .map_err(|e| {
            Error::InvalidArgument(format!("{what}: WGSL does not validate: {}", e.as_inner()))
        })
}

/// Every function of a WGSL library module (in source order), with its signature as
/// the harness needs it. Only scalar f32/u32, `texture_2d_array<f32>` and `sampler`
/// arguments and f32 scalar, vector or 3×3 matrix results occur in the generated modules;
/// anything else is a typed error naming the function.
pub fn calls(src: &str, what: &str) -> Result<Vec<Call>> {
    let module = parse(src, what)?;
    let mut out = Vec::new();
    for (_, f) in module.functions.iter() {
        let name = f.name.clone().unwrap_or_default();
        let bad = || {
            Error::InvalidArgument(format!(
                "{what}: {name} has a signature the harness cannot call"
            ))
        };
        let scalar = |ty: naga::Handle<naga::Type>| match module.types[ty].inner {
            naga::TypeInner::Scalar(s) => Some((s.kind, 1)),
            naga::TypeInner::Vector { size, scalar } => Some((scalar.kind, size as u32)),
            _ => None,
        };
        let mut args = Vec::new();
        for a in &f.arguments {
            let arg = match module.types[a.ty].inner {
                naga::TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: true,
                    class:
                        naga::ImageClass::Sampled {
                            kind: naga::ScalarKind::Float,
                            multi: false,
                        },
                } => Arg::TextureArray,
                naga::TypeInner::Sampler { comparison: false } => Arg::Sampler,
                _ => match scalar(a.ty).ok_or_else(bad)? {
                    (naga::ScalarKind::Float, 1) => Arg::F32,
                    (naga::ScalarKind::Uint, 1) => Arg::U32,
                    _ => return Err(bad()),
                },
            };
            args.push(arg);
        }
        let components = match f.result.as_ref().map(|r| &module.types[r.ty].inner) {
            Some(naga::TypeInner::Matrix {
                columns: naga::VectorSize::Tri,
                rows: naga::VectorSize::Tri,
                scalar,
            }) if scalar.kind == naga::ScalarKind::Float => 9,
            _ => match f.result.as_ref().map(|r| scalar(r.ty)) {
                Some(Some((naga::ScalarKind::Float, n))) => n,
                _ => return Err(bad()),
            },
        };
        out.push(Call {
            name,
            args,
            components,
        });
    }
    Ok(out)
}

/// The harness: two storage buffers and one compute entry point. Invocation i reads
/// its arguments from args[i·K …] (K = the largest arity) and writes result j of M to
/// out[i·M + j] (vector results summed, so every component is live).
pub fn harness(calls: &[Call]) -> String {
    let k = calls.iter().map(|c| c.args.len()).max().unwrap_or(0).max(1);
    let resources = calls
        .iter()
        .flat_map(|c| &c.args)
        .any(|a| matches!(a, Arg::TextureArray | Arg::Sampler));
    let m = calls.len().max(1);
    let mut s = format!(
        "\n// Harness (not part of the library): calls every function once per invocation.\n@group(0) @binding(0) var<storage, read> ndfb_harness_args: array<f32>;\n@group(0) @binding(1) var<storage, read_write> ndfb_harness_out: array<f32>;\n{}\n@compute @workgroup_size(64)\nfn {ENTRY}(@builtin(global_invocation_id) id: vec3<u32>) {{\n    let i = id.x;\n    if (i >= arrayLength(&ndfb_harness_out) / {m}u) {{\n        return;\n    }}\n    let a = i * {k}u;\n",
        if resources {
            "@group(0) @binding(2) var ndfb_harness_lut: texture_2d_array<f32>;\n@group(0) @binding(3) var ndfb_harness_sampler: sampler;\n"
        } else {
            ""
        }
    );
    for (j, c) in calls.iter().enumerate() {
        let args: Vec<String> = c
            .args
            .iter()
            .enumerate()
            .map(|(q, &u)| {
                let x = format!("ndfb_harness_args[a + {q}u]");
                match u {
                    Arg::F32 => x,
                    Arg::U32 => format!("u32({x})"),
                    Arg::TextureArray => "ndfb_harness_lut".into(),
                    Arg::Sampler => "ndfb_harness_sampler".into(),
                }
            })
            .collect();
        let call = format!("{}({})", c.name, args.join(", "));
        let value = match c.components {
            1 => call,
            9 => format!("dot({call} * vec3<f32>(1.0), vec3<f32>(1.0))"),
            n => format!("dot({call}, vec{n}<f32>(1.0))"),
        };
        s.push_str(&format!(
            "    ndfb_harness_out[i * {m}u + {j}u] = {value};\n"
        ));
    }
    s.push_str("}\n");
    s
}

/// A library module with its harness appended: a complete compute shader.
pub fn harnessed(src: &str, what: &str) -> Result<String> {
    Ok(format!("{src}{}", harness(&calls(src, what)?)))
}

/// What one back end produced from a shader: its bytes, or naga's error message.
#[derive(Clone, Debug)]
pub struct Output {
    pub backend: Backend,
    pub result: std::result::Result<Vec<u8>, String>,
}

/// Translate a complete compute shader (entry point [`ENTRY`]) with every back end.
/// The WGSL must parse and validate (else a typed error); each back end's own failure
/// is recorded in its [`Output`].
pub fn translate(shader: &str, what: &str) -> Result<Vec<Output>> {
    let module = parse(shader, what)?;
    let info = validate(&module, what)?;
    Ok(BACKENDS
        .iter()
        .map(|&b| Output {
            backend: b,
            result: write(b, &module, &info),
        })
        .collect())
}

/// One back end over a validated module.
pub fn write(
    b: Backend,
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
) -> std::result::Result<Vec<u8>, String> {
    use naga::back::{glsl, hlsl, msl, spv};
    let stage = naga::ShaderStage::Compute;
    match b {
        Backend::Spv => {
            let options = spv::Options {
                // no debug info: the bytes depend only on the shader and naga's version
                flags: spv::WriterFlags::empty(),
                ..Default::default()
            };
            let pipeline = spv::PipelineOptions {
                shader_stage: stage,
                entry_point: ENTRY.into(),
            };
            spv::write_vec(module, info, &options, Some(&pipeline))
                .map(|w| w.iter().flat_map(|x| x.to_le_bytes()).collect())
                .map_err(|e| e.to_string())
        }
        Backend::Msl => {
            let options = msl::Options {
                lang_version: (2, 0),
                ..Default::default()
            };
            let pipeline = msl::PipelineOptions {
                entry_point: Some((stage, ENTRY.into())),
                ..Default::default()
            };
            msl::write_string(module, info, &options, &pipeline)
                .map(|(s, _)| s.into_bytes())
                .map_err(|e| e.to_string())
        }
        Backend::Hlsl => {
            let options = hlsl::Options::default();
            let pipeline = hlsl::PipelineOptions {
                entry_point: Some((stage, ENTRY.into())),
            };
            let mut s = String::new();
            hlsl::Writer::new(&mut s, &options, &pipeline)
                .write(module, info, None)
                .map(|_| s.into_bytes())
                .map_err(|e| e.to_string())
        }
        Backend::Glsl => {
            let options = glsl::Options {
                version: glsl::Version::Desktop(450),
                writer_flags: glsl::WriterFlags::empty(),
                ..Default::default()
            };
            let pipeline = glsl::PipelineOptions {
                shader_stage: stage,
                entry_point: ENTRY.into(),
                multiview: None,
            };
            let mut s = String::new();
            glsl::Writer::new(
                &mut s,
                module,
                info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .and_then(|mut w| w.write())
            .map(|_| s.into_bytes())
            .map_err(|e| e.to_string())
        }
    }
}

/// The element counts of the arrays a SPIR-V module copies into function memory
/// (`OpVariable … Function` whose type is an array): what naga emits when a shader
/// indexes a `const` array with a dynamic index — a per-invocation copy of the whole
/// array, which drivers must then compile and run. Unknown lengths count as 0.
pub fn function_array_copies(spirv: &[u8]) -> Vec<u64> {
    use std::collections::HashMap;
    let words: Vec<u32> = spirv
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let (mut consts, mut arrays, mut fn_ptrs) = (HashMap::new(), HashMap::new(), HashMap::new());
    let mut out = Vec::new();
    let mut i = 5; // after the header
    while i < words.len() {
        let (count, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if count == 0 || i + count > words.len() {
            break;
        }
        let w = &words[i..i + count];
        match op {
            // OpConstant: result type, id, value (32-bit integers suffice for lengths)
            43 if count >= 4 => {
                consts.insert(w[2], w[3] as u64);
            }
            // OpTypeArray: id, element type, length id
            28 if count >= 4 => {
                arrays.insert(w[1], w[3]);
            }
            // OpTypePointer: id, storage class (7 = Function), type
            32 if count >= 4 && w[2] == 7 => {
                fn_ptrs.insert(w[1], w[3]);
            }
            // OpVariable: result type, id, storage class
            59 if count >= 4 && w[3] == 7 => {
                if let Some(len) = fn_ptrs.get(&w[1]).and_then(|t| arrays.get(t)) {
                    out.push(consts.get(len).copied().unwrap_or(0));
                }
            }
            _ => {}
        }
        i += count;
    }
    out
}

/// The SPIR-V instructions one call of each function in `roots` executes, from a library
/// module compiled with its harness by naga (debug names on, so functions are found by
/// name): the function's own instructions between `OpFunction` and `OpFunctionEnd`
/// (less the structural ones: `OpFunctionParameter`, `OpLabel`), plus, at each
/// `OpFunctionCall`, its callee's count. Exact for loop-free code, which every
/// generated function the count is asked of is; a function with a loop (`OpLoopMerge`)
/// is a typed error, as is a root the module does not have.
pub fn executed_instructions(src: &str, what: &str, roots: &[&str]) -> Result<Vec<usize>> {
    use naga::back::spv;
    use std::collections::HashMap;
    let module = parse(&harnessed(src, what)?, what)?;
    let info = validate(&module, what)?;
    let options = spv::Options {
        flags: spv::WriterFlags::DEBUG,
        ..Default::default()
    };
    let pipeline = spv::PipelineOptions {
        shader_stage: naga::ShaderStage::Compute,
        entry_point: ENTRY.into(),
    };
    let words = spv::write_vec(&module, &info, &options, Some(&pipeline))
        .map_err(|e| Error::InvalidArgument(format!("{what}: SPIR-V: {e}")))?;
    let (mut names, mut own, mut calls, mut looped) = (
        HashMap::new(),
        HashMap::new(),
        HashMap::<u32, Vec<u32>>::new(),
        Vec::new(),
    );
    let mut current: Option<u32> = None;
    let mut i = 5;
    while i < words.len() {
        let (count, op) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if count == 0 || i + count > words.len() {
            return Err(Error::InvalidArgument(format!(
                "{what}: SPIR-V ends mid-instruction"
            )));
        }
        let w = &words[i..i + count];
        match (op, current) {
            // OpName: target id, literal string
            (5, _) if count >= 3 => {
                let bytes: Vec<u8> = w[2..].iter().flat_map(|x| x.to_le_bytes()).collect();
                let name = String::from_utf8_lossy(&bytes)
                    .trim_end_matches('\0')
                    .to_string();
                names.insert(name, w[1]);
            }
            // OpFunction: result type, result id
            (54, _) if count >= 3 => {
                current = Some(w[2]);
                own.insert(w[2], 0usize);
            }
            // OpFunctionEnd
            (56, _) => current = None,
            // OpFunctionParameter, OpLabel: structure, not work
            (55 | 248, Some(_)) => {}
            (_, Some(f)) => {
                *own.get_mut(&f).expect("current function") += 1;
                match op {
                    // OpFunctionCall: result type, result id, callee
                    57 if count >= 4 => calls.entry(f).or_default().push(w[3]),
                    // OpLoopMerge
                    246 => looped.push(f),
                    _ => {}
                }
            }
            _ => {}
        }
        i += count;
    }
    fn total(
        f: u32,
        own: &HashMap<u32, usize>,
        calls: &HashMap<u32, Vec<u32>>,
        looped: &[u32],
        depth: usize,
    ) -> Option<usize> {
        if depth > 64 || looped.contains(&f) {
            return None;
        }
        let callees = calls.get(&f).map_or(&[][..], |v| &v[..]);
        callees.iter().try_fold(*own.get(&f)?, |s, &c| {
            Some(s + total(c, own, calls, looped, depth + 1)?)
        })
    }
    roots
        .iter()
        .map(|r| {
            let id = names.get(*r).ok_or_else(|| {
                Error::InvalidArgument(format!("{what}: no function {r} in the SPIR-V"))
            })?;
            total(*id, &own, &calls, &looped, 0).ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "{what}: {r} loops (or recurses): its executed instructions are not its count"
                ))
            })
        })
        .collect()
}
