//! The hair shader: naga parses and validates it, and a line-by-line Rust
//! port of its shading functions (below; same formulas, same order, the
//! tables read as the shader's `textureLoad`s do) matches coif's CPU
//! shading at 400 direction triples.
use coif::glam::{Vec3, Vec4};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{Lut, LutLayout, Params};
use coif_bevy::shading::{lut_textures, texel, HairShadingUniform, HAIR_WGSL};

/// Parses and validates a shader with naga (wgpu 29's, Bevy 0.19's
/// front end), panicking with its diagnostics.
fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module);
    if let Err(e) = info {
        panic!("{name}: {}", e.emit_to_string(source));
    }
    let names: Vec<&str> = module
        .functions
        .iter()
        .map(|(_, f)| f.name.as_deref().unwrap_or(""))
        .collect();
    for f in ["kajiya_kay", "marschner", "hair_radiance"] {
        assert!(names.contains(&f), "{name}: {f} missing: {names:?}");
    }
    let stages: Vec<naga::ShaderStage> = module.entry_points.iter().map(|e| e.stage).collect();
    assert_eq!(
        stages,
        [naga::ShaderStage::Vertex, naga::ShaderStage::Fragment],
        "{name}"
    );
    module
}

/// (group, binding, name) of the module's bound globals, sorted.
fn bindings(module: &naga::Module) -> Vec<(u32, u32, String)> {
    let mut out: Vec<(u32, u32, String)> = module
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
fn wgsl_parses_and_validates() {
    let module = validate("HAIR_WGSL", HAIR_WGSL);
    let b = bindings(&module);
    let want: Vec<(u32, u32, String)> = ["view", "shading", "lut_m", "lut_n0", "lut_n1"]
        .iter()
        .enumerate()
        .map(|(i, n)| (0, i as u32, n.to_string()))
        .collect();
    assert_eq!(b, want);
}

/// The material's shader: valid WGSL as it is (no Bevy import), Bevy's
/// view uniform at group 0 binding 0 and the material's four bindings in
/// bevy_pbr's material group, in the order `HairMaterial`'s `AsBindGroup`
/// derive gives them.
#[cfg(feature = "render")]
#[test]
fn material_wgsl_parses_and_validates() {
    use coif_bevy::shading::HAIR_MATERIAL_WGSL;
    let module = validate("HAIR_MATERIAL_WGSL", HAIR_MATERIAL_WGSL);
    let group = bevy::pbr::MATERIAL_BIND_GROUP_INDEX as u32;
    let mut want = vec![(0, 0, "view".to_string())];
    for (i, n) in ["shading", "lut_m", "lut_n0", "lut_n1"].iter().enumerate() {
        want.push((group, i as u32, n.to_string()));
    }
    assert_eq!(bindings(&module), want);
}

/// The material shader declares the leading fields of Bevy's `View`
/// uniform only: their offsets (naga's layout of the WGSL struct) must be
/// where Bevy's `ViewUniform` puts them (encase's layout of the Rust
/// struct, written with a marker value per field and read back there).
#[cfg(feature = "render")]
#[test]
fn material_view_prefix_matches_bevys_view_uniform() {
    use bevy::math::{Mat3, Mat4, Vec2 as BVec2, Vec3 as BVec3, Vec4 as BVec4};
    use bevy::render::render_resource::encase::UniformBuffer;
    use bevy::render::view::{ColorGradingUniform, ViewUniform};
    use coif_bevy::shading::HAIR_MATERIAL_WGSL;
    let module = naga::front::wgsl::parse_str(HAIR_MATERIAL_WGSL).expect("parses");
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("BevyViewPrefix"))
        .expect("BevyViewPrefix");
    let naga::TypeInner::Struct { members, .. } = &ty.inner else {
        panic!("not a struct");
    };
    let mat = |k: f32| Mat4::from_cols_array(&std::array::from_fn(|i| k * 100.0 + i as f32));
    let view = ViewUniform {
        clip_from_world: mat(1.0),
        unjittered_clip_from_world: mat(2.0),
        world_from_clip: mat(3.0),
        world_from_view: mat(4.0),
        view_from_world: mat(5.0),
        clip_from_view: mat(6.0),
        view_from_clip: mat(7.0),
        world_position: BVec3::new(801.0, 802.0, 803.0),
        exposure: 901.0,
        viewport: BVec4::ZERO,
        main_pass_viewport: BVec4::ZERO,
        frustum: [BVec4::ZERO; 6],
        lod_view_world_position: BVec3::ZERO,
        color_grading: ColorGradingUniform {
            balance: Mat3::ZERO,
            saturation: BVec3::ZERO,
            contrast: BVec3::ZERO,
            gamma: BVec3::ZERO,
            gain: BVec3::ZERO,
            lift: BVec3::ZERO,
            midtone_range: BVec2::ZERO,
            exposure: 0.0,
            hue: 0.0,
            post_saturation: 0.0,
        },
        mip_bias: 0.0,
        frame_count: 0,
    };
    let mut buffer = UniformBuffer::new(Vec::<u8>::new());
    buffer.write(&view).expect("encase writes the view");
    let bytes = buffer.into_inner();
    let float_at =
        |offset: usize| f32::from_le_bytes(bytes[offset..offset + 4].try_into().expect("4 bytes"));
    let want: [(&str, f32); 9] = [
        ("clip_from_world", 100.0),
        ("unjittered_clip_from_world", 200.0),
        ("world_from_clip", 300.0),
        ("world_from_view", 400.0),
        ("view_from_world", 500.0),
        ("clip_from_view", 600.0),
        ("view_from_clip", 700.0),
        ("world_position", 801.0),
        ("exposure", 901.0),
    ];
    assert_eq!(members.len(), want.len());
    for (m, (name, first)) in members.iter().zip(want) {
        assert_eq!(m.name.as_deref(), Some(name));
        assert_eq!(float_at(m.offset as usize), first, "{name} at {}", m.offset);
    }
    // The matrices' last element and the position's last component too.
    assert_eq!(float_at(members[6].offset as usize + 60), 715.0);
    assert_eq!(float_at(members[7].offset as usize + 8), 803.0);
}

/// The shader's uniform block and tables, for the port.
struct Shader {
    u: HairShadingUniform,
    tables: [Vec<[f32; 4]>; 3],
}

fn v(a: [f32; 4]) -> Vec4 {
    Vec4::from_array(a)
}

impl Shader {
    // fn kk_lobe
    fn kk_lobe(c_i: f32, c_o: f32, s_o: f32, wi_n: f32, shift: f32, exponent: f32) -> f32 {
        let k = 1.0 / (1.0 + shift * shift).sqrt();
        let (cos_tilt, sin_tilt) = (k, shift * k);
        let co = c_o * cos_tilt + s_o * sin_tilt;
        let so = (s_o * cos_tilt - c_o * sin_tilt).abs();
        let ci = (c_i * cos_tilt + wi_n * sin_tilt).clamp(-1.0, 1.0);
        let si = (1.0 - ci * ci).max(0.0).sqrt();
        let base = (si * so - ci * co).max(1e-30);
        let x = exponent.max(0.0) * base.log2();
        if x < -90.0 {
            return 0.0;
        }
        x.exp2()
    }

    // fn kajiya_kay
    fn kajiya_kay(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let tiny = 1e-30;
        if t.dot(t) < tiny || wi.dot(wi) < tiny || wo.dot(wo) < tiny {
            return Vec3::ZERO;
        }
        let c_i = wi.dot(t).clamp(-1.0, 1.0);
        let c_o = wo.dot(t).clamp(-1.0, 1.0);
        let c_io = wi.dot(wo);
        let s_i = (1.0 - c_i * c_i).max(0.0).sqrt();
        let s_o = (1.0 - c_o * c_o).max(0.0).sqrt();
        let wi_n = if s_o > 1e-6 {
            (c_io - c_i * c_o) / s_o
        } else {
            0.0
        };
        let u = &self.u;
        let p = Self::kk_lobe(c_i, c_o, s_o, wi_n, u.shifts[0], u.primary[3]);
        let s = Self::kk_lobe(c_i, c_o, s_o, wi_n, u.shifts[1], u.secondary[3]);
        v(u.diffuse).truncate() * s_i + v(u.primary).truncate() * p + v(u.secondary).truncate() * s
    }

    // fn lut_coords
    fn lut_coords(&self, uv: [f32; 2]) -> Vec4 {
        let scale = self.u.lut[0] - 1.0;
        let last = self.u.lut[0] - 2.0;
        let x = (uv[0] * scale).clamp(0.0, scale);
        let y = (uv[1] * scale).clamp(0.0, scale);
        let x0 = x.floor().clamp(0.0, last);
        let y0 = y.floor().clamp(0.0, last);
        Vec4::new(x0, y0, x - x0, y - y0)
    }

    // fn bilinear (textureLoad at integer texels; WGSL's mix is a + (b - a) t)
    fn bilinear(&self, tex: usize, c: Vec4) -> Vec4 {
        let res = self.u.lut[0] as usize;
        let (x, y) = (c.x as usize, c.y as usize);
        let load = |dx: usize, dy: usize| texel(&self.tables[tex], res, x + dx, y + dy);
        let a = load(0, 0).lerp(load(1, 0), c.z);
        let b = load(0, 1).lerp(load(1, 1), c.z);
        a.lerp(b, c.w)
    }

    // fn marschner
    fn marschner(&self, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (lt2, li2, lo2) = (t.dot(t), wi.dot(wi), wo.dot(wo));
        if lt2 < 1e-30 || li2 < 1e-30 || lo2 < 1e-30 {
            return Vec3::ZERO;
        }
        let (rt, ri, ro) = (lt2.sqrt(), li2.sqrt(), lo2.sqrt());
        let sin_i = (wi.dot(t) / (ri * rt)).clamp(-1.0, 1.0);
        let sin_o = (wo.dot(t) / (ro * rt)).clamp(-1.0, 1.0);
        let cos_i = (1.0 - sin_i * sin_i).max(0.0).sqrt();
        let cos_o = (1.0 - sin_o * sin_o).max(0.0).sqrt();
        let cc = cos_i * cos_o;
        let mut cos_phi = 1.0;
        if cc > 1e-12 {
            cos_phi = ((wi.dot(wo) / (ri * ro) - sin_i * sin_o) / cc).clamp(-1.0, 1.0);
        }
        let inv_pi = std::f32::consts::FRAC_1_PI;
        let angular = self.u.lut[1] > 0.5;
        let mut u = [0.5 + 0.5 * sin_i, 0.5 + 0.5 * sin_o];
        if angular {
            u = [0.5 + sin_i.asin() * inv_pi, 0.5 + sin_o.asin() * inv_pi];
        }
        let m = self.bilinear(0, self.lut_coords(u));
        let mut cos_d = m.w;
        let mut vv = 0.5 + 0.5 * cos_phi;
        if angular {
            cos_d = (0.5 * (1.0 + cc + sin_i * sin_o)).max(0.0).sqrt();
            vv = cos_phi.acos() * inv_pi;
        }
        let nc = self.lut_coords([cos_d, vv]);
        let n0 = self.bilinear(1, nc);
        let n1 = self.bilinear(2, nc);
        (Vec3::splat(m.x * n0.x) + Vec3::new(n0.y, n0.z, n0.w) * m.y + n1.truncate() * m.z)
            .max(Vec3::ZERO)
    }
}

/// Unit directions spread over the sphere (a Fibonacci lattice), turned
/// by `k` so that the three sets differ.
fn directions(n: usize, k: f32) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).sqrt();
            let a = golden * i as f32 + k;
            Vec3::new(r * a.cos(), y, r * a.sin()).normalize()
        })
        .collect()
}

/// Relative to the largest value over the set (bright highlights dominate;
/// a dim sample's relative error means nothing on screen).
fn compare(name: &str, got: &[Vec3], want: &[Vec3], tol: f32) {
    let peak = want.iter().map(|c| c.max_element()).fold(0.0, f32::max);
    let worst = got
        .iter()
        .zip(want)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0, f32::max);
    println!(
        "{name}: {} samples, peak {peak:.4}, worst difference {worst:.2e} ({:.2e} of the peak)",
        got.len(),
        worst / peak
    );
    assert!(peak > 0.0);
    assert!(worst <= tol * peak, "{name}: {worst} > {tol} x {peak}");
}

#[test]
fn ported_shader_matches_coif_cpu_shading() {
    let n = 400;
    let (ts, wis, wos) = (directions(n, 0.0), directions(n, 1.3), directions(n, 2.9));
    // Mix the sets so each triple is unrelated; a few exact mirror triples
    // (the highlights' peaks) too.
    let mut triples: Vec<(Vec3, Vec3, Vec3)> = (0..n)
        .map(|i| (ts[i], wis[(7 * i + 3) % n], wos[(13 * i + 5) % n]))
        .collect();
    for i in 0..16 {
        let t = ts[i * 17];
        let wi = wis[i * 23];
        let wo = (-(wi - 2.0 * wi.dot(t) * t)).normalize(); // on the specular cone
        triples[i] = (t, wi, wo);
    }
    let kk = KajiyaKay::default();
    for layout in [LutLayout::Angular, LutLayout::Nalu] {
        let lut = Lut::with_layout(&Params::default(), 64, layout);
        let u = HairShadingUniform::new(&kk, &lut, 0.5, Vec3::Y, 1.0).unwrap();
        let shader = Shader {
            u,
            tables: lut_textures(&lut),
        };
        let got: Vec<Vec3> = triples
            .iter()
            .map(|&(t, wi, wo)| shader.marschner(t, wi, wo))
            .collect();
        let want: Vec<Vec3> = triples
            .iter()
            .map(|&(t, wi, wo)| lut.scattering(t, wi, wo))
            .collect();
        compare(&format!("marschner {layout:?}"), &got, &want, 1e-4);
        if layout == LutLayout::Angular {
            let got: Vec<Vec3> = triples
                .iter()
                .map(|&(t, wi, wo)| shader.kajiya_kay(t, wi, wo))
                .collect();
            let want: Vec<Vec3> = triples
                .iter()
                .map(|&(t, wi, wo)| kk.shade(t, wi, wo))
                .collect();
            // coif's CPU path uses polynomial log2/exp2; the shader the GPU's.
            compare("kajiya-kay", &got, &want, 1e-4);
        }
    }
}
