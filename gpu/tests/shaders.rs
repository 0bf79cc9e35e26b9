//! Every WGSL module parses and validates with naga, declares the
//! bindings gpu/README.md documents, and (where spirv-val and
//! glslangValidator are installed) its SPIR-V and GLSL translations pass
//! Khronos' validators, as the `emit` example writes them.

use coif_gpu::shaders::{Stage, MODULES};
use naga::valid::{Capabilities, ValidationFlags, Validator};

// The emit example's translation, called here as the example calls it.
#[allow(dead_code)]
#[path = "../examples/emit.rs"]
mod emit;

fn parse(name: &str, source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    (module, info)
}

/// (group, binding, name) of every resource the module declares.
fn bindings(module: &naga::Module) -> Vec<(u32, u32, String)> {
    let mut out: Vec<_> = module
        .global_variables
        .iter()
        .filter_map(|(_, g)| {
            let b = g.binding.as_ref()?;
            Some((b.group, b.binding, g.name.clone().unwrap_or_default()))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn modules_validate_with_their_entry_points_and_bindings() {
    for m in MODULES {
        let (module, _) = parse(m.name, m.source);
        let entries: Vec<(&str, naga::ShaderStage)> = module
            .entry_points
            .iter()
            .map(|e| (e.name.as_str(), e.stage))
            .collect();
        for &(name, stage) in m.entry_points {
            let stage = match stage {
                Stage::Vertex => naga::ShaderStage::Vertex,
                Stage::Fragment => naga::ShaderStage::Fragment,
                Stage::Compute => naga::ShaderStage::Compute,
            };
            assert!(
                entries.contains(&(name, stage)),
                "{}: no {name} ({stage:?}) in {entries:?}",
                m.name
            );
        }
        assert_eq!(
            entries.len(),
            m.entry_points.len(),
            "{}: {entries:?}",
            m.name
        );
    }
    let (draw, _) = parse("draw", coif_gpu::shaders::DRAW_WGSL);
    let names = |v: Vec<(u32, u32, String)>| {
        v.into_iter()
            .map(|(g, b, n)| format!("{g}.{b} {n}"))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        names(bindings(&draw)),
        [
            "0.0 hair_view",
            "0.1 guides",
            "0.2 hairs",
            "1.0 shading",
            "1.1 lut_m",
            "1.2 lut_n0",
            "1.3 lut_n1"
        ]
    );
    let (compute, _) = parse("compute", coif_gpu::shaders::COMPUTE_WGSL);
    assert_eq!(
        names(bindings(&compute)),
        ["0.0 hair_view", "0.1 guides", "0.2 hairs", "0.3 vertices"]
    );
}

#[test]
fn the_hair_view_struct_has_the_rust_layout() {
    let (module, _) = parse("compute", coif_gpu::shaders::COMPUTE_WGSL);
    let layouter = {
        let mut l = naga::proc::Layouter::default();
        l.update(module.to_ctx()).expect("layout");
        l
    };
    let find = |name: &str| {
        module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name}"))
    };
    for (name, size) in [
        ("HairView", std::mem::size_of::<coif_gpu::HairView>()),
        ("RenderHair", std::mem::size_of::<coif_gpu::RenderHair>()),
        (
            "RenderVertex",
            std::mem::size_of::<coif_lod::RenderVertex>(),
        ),
    ] {
        let (handle, _) = find(name);
        assert_eq!(layouter[handle].size as usize, size, "{name}");
    }
}

/// Runs `tool args` if it is installed: Some(success), or None.
fn run(tool: &str, args: &[&std::path::Path]) -> Option<(bool, String)> {
    let out = std::process::Command::new(tool).args(args).output().ok()?;
    Some((
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    ))
}

#[test]
fn emitted_spirv_and_glsl_pass_khronos_validators() {
    let dir = std::env::temp_dir().join(format!("coif-gpu-emit-{}", std::process::id()));
    for lang in ["wgsl", "spv", "hlsl", "msl", "glsl"] {
        let files = emit::emit(lang, &dir.join(lang)).unwrap_or_else(|e| panic!("{lang}: {e}"));
        assert!(files.len() >= 2, "{lang}: {files:?}");
    }
    let mut checked = 0;
    for (tool, lang, exts) in [
        ("spirv-val", "spv", &["spv"][..]),
        ("glslangValidator", "glsl", &["vert", "frag", "comp"][..]),
    ] {
        for ext in exts {
            let file = dir.join(lang).join(format!(
                "{}.{ext}",
                if *ext == "comp" {
                    "hair_compute"
                } else {
                    "hair_draw"
                }
            ));
            assert!(file.exists(), "{}", file.display());
            if *ext == "spv" {
                let other = dir.join(lang).join("hair_compute.spv");
                if let Some((ok, log)) = run(tool, &[&other]) {
                    assert!(ok, "{tool} {}: {log}", other.display());
                }
            }
            match run(tool, &[&file]) {
                Some((ok, log)) => {
                    assert!(ok, "{tool} {}: {log}", file.display());
                    checked += 1;
                }
                None => eprintln!("{tool} not installed: {} not validated", file.display()),
            }
        }
    }
    eprintln!("{checked} emitted files passed Khronos' validators");
    let _ = std::fs::remove_dir_all(&dir);
}
