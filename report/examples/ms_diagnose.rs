//! Diagnostics of dual scattering against the path tracer, on the sets of
//! the report's `multiple scattering` family (training and held-out tufts,
//! Sintel's crown; blond, brown, dark): per set the relative RMS of dual
//! and single scattering, the per-channel bias, the multiple-scattering
//! part alone (dual minus `D S` against the traced orders 2 and up) and
//! dual scattering with each patch's mean hair behind instead of each
//! hit's exact count; per patch (`-v`; the crown always) the tracer's
//! orders 1, 2, 3, 4+ (paths cut after 1, 2, 3 scatterings), the hits'
//! mean `n`, `m`, `D`, the hair behind over the hemisphere, and dual
//! scattering's terms (`D S`, the local backscatter, the scattered light).
//!
//! `cargo run --release -p coif-report --example ms_diagnose -- [--crown]
//! [-v] [-g] [--grid] [--rays N] [--paths N] [--crown-radius MM]`:
//! `--crown` the crown only, `--crown-radius` its ball's radius (default
//! `CROWN_BALL_RADIUS`),
//! `-g` the hits grouped by `(D, m, n)` with the traced and modelled terms
//! of each group, `--grid` the density grid of `MULTIPLE_SCATTERING.md`
//! (steps of 0.05 over [0.1, 0.7]^2, optimum of blond^2 + brown^2 on the
//! training set) with every set at the optimum and at the defaults.

use coif::shading::dual_scattering::accuracy::HitLighting;
use coif::shading::dual_scattering::{DualScattering, DualScatteringSettings};
use coif::shading::pbrt;
use coif_report::multiple_scattering::diagnose::{run, PatchInfo, Traced};
use coif_report::multiple_scattering::CROWN_BALL_RADIUS;
use glam::{DVec3, Vec3};

/// Pairs of (estimate, traced) patch means.
type Pairs = Vec<(Vec3, Vec3)>;
/// Grid results: colour, set, d_f, d_b, relative RMS.
type GridRow = (String, String, f32, f32, f64);

fn arg(args: &[String], name: &str) -> Option<String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1).cloned())
}

fn terms(ds: &DualScattering, table: &pbrt::Table, hits: &[Option<HitLighting>]) -> [Vec3; 5] {
    // D S, D back, scattered, dual, and geometry (mean n, mean m, mean D).
    let mut acc = [DVec3::ZERO; 5];
    for h in hits.iter().flatten() {
        let s = table.scattering(h.tangent, h.wi, h.wo);
        let f = ds.shade_layered(s, h.tangent, h.wi, h.wo, h.fibres, h.behind, h.direct);
        let back = ds.shade_layered(Vec3::ZERO, h.tangent, h.wi, h.wo, 0.0, h.behind, 1.0);
        if !(f.is_finite() && s.is_finite()) {
            continue;
        }
        let ds_ = (s * h.direct).as_dvec3();
        let db = (back * h.direct).as_dvec3();
        acc[0] += ds_;
        acc[1] += db;
        acc[2] += f.as_dvec3() - ds_ - db;
        acc[3] += f.as_dvec3();
        acc[4] += DVec3::new(h.fibres as f64, h.behind as f64, h.direct as f64);
    }
    let n = hits.len().max(1) as f64;
    let hit_count = hits.iter().flatten().count().max(1) as f64;
    [
        (acc[0] / n).as_vec3(),
        (acc[1] / n).as_vec3(),
        (acc[2] / n).as_vec3(),
        (acc[3] / n).as_vec3(),
        (acc[4] / hit_count).as_vec3(),
    ]
}

fn rel(pairs: &[(Vec3, Vec3)]) -> f64 {
    let (mut e, mut r) = (0.0, 0.0);
    for (a, b) in pairs {
        e += (*a - *b).as_dvec3().length_squared();
        r += b.as_dvec3().length_squared();
    }
    (e / r.max(1e-300)).sqrt()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let crown = args.iter().any(|a| a == "--crown");
    let rays: usize = arg(&args, "--rays").map_or(512, |s| s.parse().unwrap());
    let paths: usize = arg(&args, "--paths").map_or(64, |s| s.parse().unwrap());
    let verbose = args.iter().any(|a| a == "-v");
    let group = args.iter().any(|a| a == "-g");
    let grid = args.iter().any(|a| a == "--grid");
    let crown_radius: f32 =
        arg(&args, "--crown-radius").map_or(CROWN_BALL_RADIUS, |s| s.parse().unwrap());
    let results: std::cell::RefCell<Vec<GridRow>> = Default::default();
    run(
        rays,
        paths,
        crown,
        crown_radius,
        |name, eumelanin, infos: &[PatchInfo], traced: &[Traced]| {
            let sigma_a = pbrt::sigma_a_from_concentration(eumelanin, 0.0);
            let params = pbrt::Params {
                sigma_a,
                ..pbrt::Params::default()
            };
            let table = pbrt::Table::new(&params, 64).unwrap();
            let ds = DualScattering::from_pbrt(&table, DualScatteringSettings::default()).unwrap();
            if grid {
                for i in 2..=14 {
                    for j in 2..=14 {
                        let (d_f, d_b) = (i as f32 * 0.05, j as f32 * 0.05);
                        let ds = DualScattering::from_pbrt(
                            &table,
                            DualScatteringSettings {
                                forward_density: d_f,
                                backward_density: d_b,
                                ..DualScatteringSettings::default()
                            },
                        )
                        .unwrap();
                        let mut sets: std::collections::BTreeMap<&str, Vec<(Vec3, Vec3)>> =
                            Default::default();
                        for (p, t) in infos.iter().zip(traced) {
                            let [_, _, _, f, _] = terms(&ds, &table, p.hits);
                            sets.entry(p.set).or_default().push((f, t.cut[3]));
                        }
                        for (set, v) in sets {
                            results.borrow_mut().push((
                                name.to_string(),
                                set.to_string(),
                                d_f,
                                d_b,
                                rel(&v),
                            ));
                        }
                    }
                }
            }
            let mut per_set: std::collections::BTreeMap<&str, (Pairs, Pairs, Pairs)> =
                Default::default();
            let mut per_set_smooth: std::collections::BTreeMap<&str, Vec<(Vec3, Vec3)>> =
                Default::default();
            let mut ms_part: std::collections::BTreeMap<&str, [DVec3; 4]> = Default::default();
            for (k, (p, t)) in infos.iter().zip(traced).enumerate() {
                let [s, b, g, f, geo] = terms(&ds, &table, p.hits);
                // The same with every hit's `behind` replaced by the patch's
                // mean (what a shadow map wider than the fibres' spacing sees).
                let smooth: Vec<Option<HitLighting>> = p
                    .hits
                    .iter()
                    .map(|h| h.map(|h| HitLighting { behind: geo.y, ..h }))
                    .collect();
                let f_smooth = terms(&ds, &table, &smooth)[3];
                per_set_smooth
                    .entry(p.set)
                    .or_default()
                    .push((f_smooth, t.cut[3]));
                let all = t.cut[3];
                let e2 = ms_part.entry(p.set).or_insert([DVec3::ZERO; 4]);
                e2[0] += (f - s).as_dvec3();
                e2[1] += (all - t.cut[0]).as_dvec3();
                e2[2] += b.as_dvec3();
                e2[3] += g.as_dvec3();
                let e = per_set.entry(p.set).or_default();
                e.0.push((f, all));
                e.1.push((s, all));
                e.2.push((all + t.standard_error, all));
                if group || (verbose && p.set == "crown") {
                    groups(name, p.set, k, &ds, &table, p.hits, &t.per_ray);
                }
                if verbose || p.set == "crown" {
                    println!(
                    "{name} {} #{k}: n {:.3} m {:.3} D {:.3}; behind on the line {:.3}, over the hemisphere {:.3}",
                    p.set, geo.x, geo.y, geo.z, p.behind.0, p.behind.1
                );
                    for c in 0..3 {
                        let o1 = t.cut[0][c];
                        let o2 = t.cut[1][c] - t.cut[0][c];
                        let o3 = t.cut[2][c] - t.cut[1][c];
                        let o4 = t.cut[3][c] - t.cut[2][c];
                        println!(
                        "  {}: traced {:.5} (se {:.5}) [o1 {:.5} o2 {:.5} o3 {:.5} o4+ {:.5}]  DS {:.5} back {:.5} scat {:.5} dual {:.5} ({:+.1} %) single ({:+.1} %)",
                        ["R", "G", "B"][c],
                        all[c],
                        t.standard_error[c],
                        o1, o2, o3, o4,
                        s[c], b[c], g[c], f[c],
                        100.0 * (f[c] / all[c] - 1.0),
                        100.0 * (s[c] / all[c] - 1.0),
                    );
                    }
                }
            }
            for (set, v) in &per_set_smooth {
                println!(
                    "{name} {set}: dual with the patch's mean hair behind {:.4}",
                    rel(v)
                );
            }
            for (set, v) in &ms_part {
                let r = v[0] / v[1];
                println!(
                "{name} {set}: multiple part model/traced RGB {:.3} {:.3} {:.3} (back share {:.2} {:.2} {:.2})",
                r.x, r.y, r.z,
                v[2].x / v[0].x, v[2].y / v[0].y, v[2].z / v[0].z
            );
            }
            for (set, (d, s, n)) in &per_set {
                let bias = |v: &Vec<(Vec3, Vec3)>| {
                    let (a, b) = v.iter().fold((DVec3::ZERO, DVec3::ZERO), |(a, b), (x, y)| {
                        (a + x.as_dvec3(), b + y.as_dvec3())
                    });
                    (a / b - DVec3::ONE) * 100.0
                };
                let (bd, bs) = (bias(d), bias(s));
                println!(
                "{name} {set}: bias %% RGB dual {:+.1} {:+.1} {:+.1} single {:+.1} {:+.1} {:+.1}",
                bd.x, bd.y, bd.z, bs.x, bs.y, bs.z
            );
                println!(
                    "{name} {set}: dual {:.4} single {:.4} noise {:.4} ratio {:.2}",
                    rel(d),
                    rel(s),
                    rel(n),
                    rel(s) / rel(d)
                );
            }
        },
    );
    if grid {
        let r = results.borrow();
        let get = |c: &str, s: &str, f: f32, b: f32| {
            r.iter()
                .find(|x| x.0 == c && x.1 == s && x.2 == f && x.3 == b)
                .map_or(f64::NAN, |x| x.4)
        };
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for x in r.iter().filter(|x| x.0 == "blond" && x.1 == "training") {
            let cost = x.4 * x.4 + get("brown", "training", x.2, x.3).powi(2);
            if cost < best.0 {
                best = (cost, x.2, x.3);
            }
        }
        println!(
            "grid optimum on training (blond^2 + brown^2): {:.5} at ({:.2}, {:.2})",
            best.0, best.1, best.2
        );
        for (f, b) in [(best.1, best.2), (0.4, 0.35)] {
            for c in ["blond", "brown", "dark"] {
                println!(
                    "  ({f:.2}, {b:.2}) {c}: training {:.4} held-out {:.4} crown {:.4}",
                    get(c, "training", f, b),
                    get(c, "held-out", f, b),
                    get(c, "crown", f, b)
                );
            }
        }
        let mut rows: Vec<_> = r
            .iter()
            .filter(|x| x.0 == "blond" && x.1 == "training")
            .map(|x| {
                (
                    x.4 * x.4 + get("brown", "training", x.2, x.3).powi(2),
                    x.2,
                    x.3,
                )
            })
            .collect();
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (c, f, b) in rows.iter().take(8) {
            println!(
                "  {c:.5} ({f:.2}, {b:.2}) blond crown {:.4} held-out {:.4}",
                get("blond", "crown", *f, *b),
                get("blond", "held-out", *f, *b)
            );
        }
    }
}

/// Hits grouped by (D, m up to 3, n up to 2): count, traced (all, first
/// order, the rest) and the model's terms, red and green.
fn groups(
    name: &str,
    set: &str,
    k: usize,
    ds: &DualScattering,
    table: &pbrt::Table,
    hits: &[Option<HitLighting>],
    per_ray: &[[Vec3; 3]],
) {
    let mut g: std::collections::BTreeMap<(u32, u32, u32), (usize, [DVec3; 6])> =
        Default::default();
    for (h, r) in hits.iter().zip(per_ray) {
        let Some(h) = h else { continue };
        let key = (
            h.direct as u32,
            (h.behind as u32).min(3),
            (h.fibres as u32).min(2),
        );
        let s = table.scattering(h.tangent, h.wi, h.wo);
        let f = ds.shade_layered(s, h.tangent, h.wi, h.wo, h.fibres, h.behind, h.direct);
        let back =
            ds.shade_layered(Vec3::ZERO, h.tangent, h.wi, h.wo, 0.0, h.behind, 1.0) * h.direct;
        let e = g.entry(key).or_insert((0, [DVec3::ZERO; 6]));
        e.0 += 1;
        let v = [
            r[2],
            r[0],
            r[2] - r[0],
            s * h.direct,
            back,
            f - s * h.direct - back,
        ];
        for (a, b) in e.1.iter_mut().zip(v) {
            *a += b.as_dvec3();
        }
    }
    let total: usize = g.values().map(|e| e.0).sum();
    println!("{name} {set} #{k} groups (D, m, n): {total} hits");
    for (key, (c, v)) in g {
        let m = |i: usize| v[i] / c as f64;
        println!(
            "  {key:?} {c:4}: traced R {:.5} (o1 {:.5} rest {:.5}) DS {:.5} back {:.5} scat {:.5} | G rest {:.5} back {:.5} scat {:.5}",
            m(0).x, m(1).x, m(2).x, m(3).x, m(4).x, m(5).x, m(2).y, m(4).y, m(5).y
        );
    }
}
