// coif's hair shading in WGSL: Kajiya-Kay with Scheuermann's two shifted
// highlights, and Marschner from coif's factored lookup tables
// (coif::shading::marschner::Lut, built on the CPU and uploaded as three
// rgba32float textures; the shader only looks them up, bilinearly, with
// textureLoad, as Lut::scattering does: rgba32float is not filterable
// everywhere). Directions: t the hair's unit tangent, wi to the light, wo to
// the eye, both pointing away from the fibre.
//
// This file has the shading functions only: they read the module-scope
// `shading` uniform and the `lut_m`, `lut_n0`, `lut_n1` textures, which the
// module it is part of binds: coif-gpu's `hair_draw` pipeline
// (shaders/draw.wgsl), and in coif-bevy the GPU path's material and the CPU
// mesh path's (hair_standalone.wgsl or hair_material.wgsl, then
// hair_mesh.wgsl). Every module is validated by naga at test time
// (gpu/tests/shaders.rs, coif-bevy/tests/wgsl.rs, which also checks a
// line-by-line Rust port of these functions against coif's CPU shading).

struct HairShading {
    // Kajiya-Kay: diffuse K_d (w unused), each highlight's colour (rgb) and
    // exponent (w), and their tangent shifts (x primary, y secondary).
    diffuse: vec4<f32>,
    primary: vec4<f32>,
    secondary: vec4<f32>,
    shifts: vec4<f32>,
    // x: the LUT's resolution, y: 1 = angular layout (coif's default), 0 =
    // Nalu's; z: the Marschner weight (0 = Kajiya-Kay only, 1 = Marschner
    // only); w unused.
    lut: vec4<f32>,
    // The light: direction to it (xyz), intensity (w).
    light: vec4<f32>,
};

const MIN_LENGTH_SQUARED: f32 = 1e-30;
const MIN_SIN_O: f32 = 1e-6;
const MIN_BASE: f32 = 1e-30;
const MIN_LOG2_LOBE: f32 = -90.0;
const MIN_COS_PRODUCT: f32 = 1e-12;
const INV_PI: f32 = 0.31830988618379067;

// The cone term of one highlight, its tangent tilted by atan(shift) toward
// the view direction projected into the normal plane.
fn kk_lobe(c_i: f32, c_o: f32, s_o: f32, wi_n: f32, shift: f32, exponent: f32) -> f32 {
    let k = 1.0 / sqrt(1.0 + shift * shift);
    let cos_tilt = k;
    let sin_tilt = shift * k;
    let co = c_o * cos_tilt + s_o * sin_tilt;
    let so = abs(s_o * cos_tilt - c_o * sin_tilt);
    let ci = clamp(c_i * cos_tilt + wi_n * sin_tilt, -1.0, 1.0);
    let si = sqrt(max(1.0 - ci * ci, 0.0));
    let base = max(si * so - ci * co, MIN_BASE);
    let x = max(exponent, 0.0) * log2(base);
    if x < MIN_LOG2_LOBE {
        return 0.0;
    }
    return exp2(x);
}

// Kajiya-Kay diffuse plus two highlights (coif::shading::kajiya_kay).
fn kajiya_kay(t: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if dot(t, t) < MIN_LENGTH_SQUARED || dot(wi, wi) < MIN_LENGTH_SQUARED || dot(wo, wo) < MIN_LENGTH_SQUARED {
        return vec3<f32>(0.0);
    }
    let c_i = clamp(dot(wi, t), -1.0, 1.0);
    let c_o = clamp(dot(wo, t), -1.0, 1.0);
    let c_io = dot(wi, wo);
    let s_i = sqrt(max(1.0 - c_i * c_i, 0.0));
    let s_o = sqrt(max(1.0 - c_o * c_o, 0.0));
    var wi_n = 0.0;
    if s_o > MIN_SIN_O {
        wi_n = (c_io - c_i * c_o) / s_o;
    }
    let p = kk_lobe(c_i, c_o, s_o, wi_n, shading.shifts.x, shading.primary.w);
    let s = kk_lobe(c_i, c_o, s_o, wi_n, shading.shifts.y, shading.secondary.w);
    return shading.diffuse.xyz * s_i + shading.primary.xyz * p + shading.secondary.xyz * s;
}

// Lower texel and bilinear weights of table coordinates (u, v) in [0, 1].
fn lut_coords(uv: vec2<f32>) -> vec4<f32> {
    let scale = shading.lut.x - 1.0;
    let last = shading.lut.x - 2.0;
    let x = clamp(uv.x * scale, 0.0, scale);
    let y = clamp(uv.y * scale, 0.0, scale);
    let x0 = clamp(floor(x), 0.0, last);
    let y0 = clamp(floor(y), 0.0, last);
    return vec4<f32>(x0, y0, x - x0, y - y0);
}

fn bilinear(tex: texture_2d<f32>, c: vec4<f32>) -> vec4<f32> {
    let p = vec2<i32>(i32(c.x), i32(c.y));
    let a = mix(textureLoad(tex, p, 0), textureLoad(tex, p + vec2<i32>(1, 0), 0), c.z);
    let b = mix(textureLoad(tex, p + vec2<i32>(0, 1), 0), textureLoad(tex, p + vec2<i32>(1, 1), 0), c.z);
    return mix(a, b, c.w);
}

// Marschner's S from coif's tables (Lut::scattering): M at the two
// longitudinal angles, N at (cos theta_d, azimuth).
fn marschner(t: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let lt2 = dot(t, t);
    let li2 = dot(wi, wi);
    let lo2 = dot(wo, wo);
    if lt2 < MIN_LENGTH_SQUARED || li2 < MIN_LENGTH_SQUARED || lo2 < MIN_LENGTH_SQUARED {
        return vec3<f32>(0.0);
    }
    let rt = sqrt(lt2);
    let ri = sqrt(li2);
    let ro = sqrt(lo2);
    let sin_i = clamp(dot(wi, t) / (ri * rt), -1.0, 1.0);
    let sin_o = clamp(dot(wo, t) / (ro * rt), -1.0, 1.0);
    let cos_i = sqrt(max(1.0 - sin_i * sin_i, 0.0));
    let cos_o = sqrt(max(1.0 - sin_o * sin_o, 0.0));
    let cc = cos_i * cos_o;
    var cos_phi = 1.0;
    if cc > MIN_COS_PRODUCT {
        cos_phi = clamp((dot(wi, wo) / (ri * ro) - sin_i * sin_o) / cc, -1.0, 1.0);
    }
    let angular = shading.lut.y > 0.5;
    var u = vec2<f32>(0.5 + 0.5 * sin_i, 0.5 + 0.5 * sin_o);
    if angular {
        u = vec2<f32>(0.5 + asin(sin_i) * INV_PI, 0.5 + asin(sin_o) * INV_PI);
    }
    let m = bilinear(lut_m, lut_coords(u));
    var cos_d = m.w;
    var v = 0.5 + 0.5 * cos_phi;
    if angular {
        cos_d = sqrt(max(0.5 * (1.0 + cc + sin_i * sin_o), 0.0));
        v = acos(cos_phi) * INV_PI;
    }
    let nc = lut_coords(vec2<f32>(cos_d, v));
    let n0 = bilinear(lut_n0, nc);
    let n1 = bilinear(lut_n1, nc);
    return max(vec3<f32>(m.x * n0.x) + n0.yzw * m.y + n1.xyz * m.z, vec3<f32>(0.0));
}

// The blend of the two models for a light of unit intensity from wi (what
// an engine multiplies by each of its lights' colour and shadow).
fn hair_scattering(t: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let w = shading.lut.z;
    return kajiya_kay(t, wi, wo) * (1.0 - w) + marschner(t, wi, wo) * w;
}

// The hair's radiance toward the eye under the uniform's own light:
// hair_scattering times its intensity.
fn hair_radiance(t: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return hair_scattering(t, wi, wo) * shading.light.w;
}
