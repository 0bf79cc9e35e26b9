//! Writes coif-gpu's shaders for another engine, translated by naga:
//!
//! ```text
//! cargo run --release -p coif-gpu --example emit -- <wgsl|spv|hlsl|msl|glsl> OUT_DIR
//! ```
//!
//! - `wgsl`: `hair_draw.wgsl`, `hair_compute.wgsl` (the sources);
//! - `spv`: `hair_draw.spv`, `hair_compute.spv` (SPIR-V 1.0 modules with
//!   every entry point; `spirv-val` accepts them);
//! - `hlsl`: `hair_draw.hlsl`, `hair_compute.hlsl` (shader model 5.1);
//! - `msl`: `hair_draw.metal`, `hair_compute.metal` (MSL 2.1);
//! - `glsl`: one file per entry point, named by stage for
//!   `glslangValidator`: `hair_draw.vert`, `hair_draw.frag`,
//!   `hair_compute.comp` (GLSL 4.50 core).
//!
//! Bindings keep WGSL's groups and bindings: SPIR-V and GLSL as
//! `set`/`binding`, HLSL as `register(_, spaceN)`, MSL as buffer and
//! texture slots in declaration order (gpu/README.md has the table).

use coif_gpu::shaders::{Stage, MODULES};
use naga::back::{glsl, hlsl, msl, spv};
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use std::path::Path;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [lang, out] = args.as_slice() else {
        eprintln!("usage: emit <wgsl|spv|hlsl|msl|glsl> OUT_DIR");
        return ExitCode::from(2);
    };
    match emit(lang, Path::new(out)) {
        Ok(files) => {
            for f in files {
                println!("{f}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("emit: {e}");
            ExitCode::FAILURE
        }
    }
}

pub fn emit(lang: &str, out: &Path) -> Result<Vec<String>, String> {
    if !["wgsl", "spv", "hlsl", "msl", "glsl"].contains(&lang) {
        return Err(format!(
            "unknown language {lang:?}: wgsl, spv, hlsl, msl or glsl"
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut written = Vec::new();
    for m in MODULES {
        let module = naga::front::wgsl::parse_str(m.source)
            .map_err(|e| format!("{}: {}", m.name, e.emit_to_string(m.source)))?;
        let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&module)
            .map_err(|e| format!("{}: {}", m.name, e.emit_to_string(m.source)))?;
        let mut files: Vec<(String, Vec<u8>)> = Vec::new();
        match lang {
            "wgsl" => files.push((format!("{}.wgsl", m.name), m.source.as_bytes().to_vec())),
            "spv" => {
                let options = spv::Options {
                    lang_version: (1, 0),
                    ..Default::default()
                };
                let words = spv::write_vec(&module, &info, &options, None)
                    .map_err(|e| format!("{}: {e}", m.name))?;
                let bytes = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                files.push((format!("{}.spv", m.name), bytes));
            }
            "hlsl" => {
                let options = hlsl::Options {
                    shader_model: hlsl::ShaderModel::V5_1,
                    ..Default::default()
                };
                let mut text = String::new();
                let pipeline = hlsl::PipelineOptions::default();
                hlsl::Writer::new(&mut text, &options, &pipeline)
                    .write(&module, &info, None)
                    .map_err(|e| format!("{}: {e}", m.name))?;
                files.push((format!("{}.hlsl", m.name), text.into_bytes()));
            }
            "msl" => {
                let options = msl::Options {
                    lang_version: (2, 1),
                    ..Default::default()
                };
                let (text, _) =
                    msl::write_string(&module, &info, &options, &msl::PipelineOptions::default())
                        .map_err(|e| format!("{}: {e}", m.name))?;
                files.push((format!("{}.metal", m.name), text.into_bytes()));
            }
            _ => {
                for &(entry, stage) in m.entry_points {
                    let (ext, shader_stage) = match stage {
                        Stage::Vertex => ("vert", naga::ShaderStage::Vertex),
                        Stage::Fragment => ("frag", naga::ShaderStage::Fragment),
                        Stage::Compute => ("comp", naga::ShaderStage::Compute),
                    };
                    files.push((
                        format!("{}.{ext}", m.name),
                        glsl_entry(&module, &info, entry, shader_stage)
                            .map_err(|e| format!("{}.{ext}: {e}", m.name))?
                            .into_bytes(),
                    ));
                }
            }
        }
        for (name, bytes) in files {
            let path = out.join(&name);
            std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
            written.push(path.display().to_string());
        }
    }
    Ok(written)
}

fn glsl_entry(
    module: &naga::Module,
    info: &ModuleInfo,
    entry: &str,
    stage: naga::ShaderStage,
) -> Result<String, glsl::Error> {
    let options = glsl::Options {
        version: glsl::Version::Desktop(450),
        ..Default::default()
    };
    let pipeline = glsl::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.to_string(),
        multiview: None,
    };
    let mut text = String::new();
    let mut writer = glsl::Writer::new(
        &mut text,
        module,
        info,
        &options,
        &pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )?;
    writer.write()?;
    Ok(text)
}
