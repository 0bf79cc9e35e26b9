//! The hair shader: naga parses and validates it, and a line-by-line Rust
//! port of its shading functions (below; same formulas, same order, the
//! tables read as the shader's `textureLoad`s do) matches coif's CPU
//! shading at 400 direction triples.
use coif::glam::{Vec3, Vec4};
use coif::shading::kajiya_kay::KajiyaKay;
use coif::shading::marschner::{Lut, LutLayout, Params};
use coif_bevy::shading::{lut_textures, texel, HairShadingUniform, HAIR_WGSL};

#[test]
fn wgsl_parses_and_validates() {
    let module = naga::front::wgsl::parse_str(HAIR_WGSL)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(HAIR_WGSL)));
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module);
    if let Err(e) = info {
        panic!("{}", e.emit_to_string(HAIR_WGSL));
    }
    let names: Vec<&str> = module
        .functions
        .iter()
        .map(|(_, f)| f.name.as_deref().unwrap_or(""))
        .collect();
    for f in ["kajiya_kay", "marschner", "hair_radiance"] {
        assert!(names.contains(&f), "{f} missing: {names:?}");
    }
    assert_eq!(module.entry_points.len(), 2);
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
