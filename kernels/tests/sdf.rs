//! The mesh signed distance field (`Sdf`): accuracy against brute force on
//! the shared Sintel bust (skipped when `../shared` is absent) and on small
//! meshes made here (an icosphere, and the same sphere with a cap cut off),
//! the sign by the winding number, values outside the grid, refusals of bad
//! input, the rigid transform, and no allocation per lookup.
//!
//! The brute force here is independent of the library's code: the distance
//! to a triangle is the plane distance where the projection falls inside
//! (barycentric test) and the nearest edge otherwise, and the winding number
//! sums Van Oosterom and Strackee's solid angles over all triangles, in f64.

use coif_kernels::{Error, Sdf, MAX_SDF_CELLS};
use coif_testkit::meshes::{brute, icosphere, open_sphere, Mesh};
use glam::{Affine3A, Quat, Vec3};
use std::time::Instant;

#[global_allocator]
static GLOBAL: coif_testkit::counting::Counting = coif_testkit::counting::Counting;

/// xorshift64*: uniform floats in [0, 1).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.f()
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1., 1.),
                self.range(-1., 1.),
                self.range(-1., 1.),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

struct Accuracy {
    median: f64,
    p95: f64,
    max: f64,
    sign_checked: usize,
    sign_wrong: usize,
    /// Points with `|w - 1/2| < AMBIGUOUS_W` (and |d| >= sign_from), and
    /// how many of them got the other side.
    ambiguous: usize,
    ambiguous_wrong: usize,
    samples: usize,
}

impl Accuracy {
    fn print(&self, what: &str) {
        eprintln!(
            "{what}: |error| over {} points within 2 cm: median {:.3} mm, p95 {:.3} mm, max {:.3} mm; \
             sign wrong {}/{} where |d| >= 8 mm (and {}/{} more with |w - 1/2| < {AMBIGUOUS_W})",
            self.samples,
            self.median * 1e3,
            self.p95 * 1e3,
            self.max * 1e3,
            self.sign_wrong,
            self.sign_checked,
            self.ambiguous_wrong,
            self.ambiguous
        );
    }
}

/// Winding numbers this close to 1/2 are ambiguous (see `accuracy`).
const AMBIGUOUS_W: f64 = 0.05;

/// Random points within `band` of the surface (a random point of a random
/// triangle, moved a random distance up to `band` in a random direction,
/// kept if its exact distance is within `band`): |sdf - signed truth|, and
/// the sign against `w >= 1/2` where the exact distance is at least
/// `sign_from`.
fn accuracy(m: &Mesh, sdf: &Sdf, band: f32, sign_from: f64, n: usize, seed: u64) -> Accuracy {
    let mut rng = Rng(seed);
    let mut errors = vec![];
    let (mut checked, mut wrong, mut ambiguous, mut ambiguous_wrong) = (0, 0, 0, 0);
    while errors.len() < n {
        let t = &m.1[(rng.f() * m.1.len() as f32) as usize % m.1.len()];
        let [a, b, c] = t.map(|i| m.0[i as usize]);
        let (mut u, mut v) = (rng.f(), rng.f());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        let p = a + (b - a) * u + (c - a) * v + rng.unit() * rng.range(0.0, band);
        let (d, w) = brute(m, p);
        if d > band as f64 {
            continue;
        }
        let inside = w >= 0.5;
        let truth = if inside { -d } else { d };
        let got = sdf.distance(p) as f64;
        errors.push((got - truth).abs());
        // Within 0.05 of w = 1/2 (only across a hole, next to its rim) the
        // side is ambiguous and a continuous field blends the jump there:
        // counted apart.
        if d >= sign_from {
            if (w - 0.5).abs() < AMBIGUOUS_W {
                ambiguous += 1;
                if (got < 0.0) != inside {
                    ambiguous_wrong += 1;
                }
                continue;
            }
            checked += 1;
            if (got < 0.0) != inside {
                wrong += 1;
                eprintln!("sign wrong at {p}: sdf {got:.4}, exact {d:.4}, w {w:.3}");
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    Accuracy {
        median: errors[n / 2],
        p95: errors[n * 95 / 100],
        max: errors[n - 1],
        sign_checked: checked,
        sign_wrong: wrong,
        ambiguous,
        ambiguous_wrong,
        samples: n,
    }
}

/// Points 1 mm to 100 m outside the grid box: positive, and at least half
/// (in fact at least) the exact distance.
fn check_outside(m: &Mesh, sdf: &Sdf, seed: u64) {
    let mut rng = Rng(seed);
    let (lo, hi) = sdf.bounds();
    let (c, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    for i in 0..300 {
        let dir = rng.unit();
        // From the centre to the box along dir, then beyond.
        let t_box = (half / dir.abs()).min_element();
        let beyond = 10f32.powf(rng.range(-3.0, 2.0));
        let p = c + dir * (t_box + beyond);
        let got = sdf.distance(p);
        let (d, _) = brute(m, p);
        assert!(got > 0.0, "{i}: {p} gives {got}");
        assert!(got as f64 >= 0.5 * d, "{i}: {p} gives {got} < half of {d}");
        assert!(
            got as f64 >= d * (1.0 - 1e-4) - 1e-4,
            "{i}: {got} below {d}"
        );
    }
}

#[test]
fn icosphere_is_accurate_and_signed() {
    let r = 0.1;
    let m = icosphere(4, r); // 5,120 triangles, 1.2 cm edges
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
    let acc = accuracy(&m, &sdf, 0.02, 0.008, 1500, 7);
    acc.print("icosphere r 10 cm, 5,120 triangles, 4 mm cells");
    assert!(acc.median <= 0.5e-3 && acc.p95 <= 2e-3, "{}", acc.samples);
    assert_eq!(acc.sign_wrong, 0);
    // Deep inside: negative, about -r at the centre.
    let c = sdf.distance(Vec3::ZERO);
    assert!((c + r).abs() < 0.004, "{c}");
    check_outside(&m, &sdf, 8);
}

#[test]
fn open_sphere_is_signed_by_the_winding_number() {
    let m = open_sphere(4, 0.1, 0.6);
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
    let acc = accuracy(&m, &sdf, 0.02, 0.008, 1500, 9);
    acc.print("bowl (icosphere cut at y > 0.6 r), 4 mm cells");
    assert!(acc.median <= 0.5e-3 && acc.p95 <= 2e-3);
    assert_eq!(acc.sign_wrong, 0);
    // The centre of the bowl (w about 0.9) is inside, and far below too.
    assert!(sdf.distance(Vec3::ZERO) < -0.05);
    // Well above the opening (w small) is outside.
    assert!(sdf.distance(Vec3::new(0.0, 0.12, 0.0)) > 0.0);
    check_outside(&m, &sdf, 10);
}

#[test]
fn sintel_bust_is_accurate_at_4mm() {
    let Some(m) = coif_testkit::sintel_bust() else {
        return;
    };
    assert_eq!((m.0.len(), m.1.len()), (3046, 5952));
    let t = Instant::now();
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
    let build = t.elapsed();
    let acc = accuracy(&m, &sdf, 0.02, 0.008, 3000, 11);
    acc.print(&format!(
        "Sintel bust, 4 mm cells, {:?} = {} nodes, built in {:.1} ms",
        sdf.dims(),
        sdf.node_count(),
        build.as_secs_f64() * 1e3
    ));
    assert!(acc.median <= 0.5e-3, "median {}", acc.median);
    assert!(acc.p95 <= 2e-3, "p95 {}", acc.p95);
    assert_eq!(acc.sign_wrong, 0);
    check_outside(&m, &sdf, 12);
}

/// A unit tetrahedron (outward, counter-clockwise).
fn tetra() -> Mesh {
    (
        vec![
            Vec3::ZERO,
            Vec3::new(0.1, 0.0, 0.0),
            Vec3::new(0.0, 0.1, 0.0),
            Vec3::new(0.0, 0.0, 0.1),
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

#[test]
fn bad_meshes_are_refused_without_panic_or_huge_allocation() {
    let (p, t) = tetra();
    assert_eq!(
        Sdf::from_mesh(&p, &[], 0.01).unwrap_err(),
        Error::NoTriangles
    );
    assert!(matches!(
        Sdf::from_mesh(&p, &[[0, 1, 4]], 0.01),
        Err(Error::IndexOutOfRange {
            triangle: 0,
            index: 4,
            vertices: 4
        })
    ));
    assert!(matches!(
        Sdf::from_mesh(&[], &t, 0.01),
        Err(Error::IndexOutOfRange { .. })
    ));
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut q = p.clone();
        q[2].y = bad;
        assert_eq!(
            Sdf::from_mesh(&q, &t, 0.01).unwrap_err(),
            Error::NonFinite { index: 2 }
        );
    }
    for cell in [f32::NAN, f32::INFINITY, 0.0, -0.01, f32::NEG_INFINITY] {
        assert!(matches!(
            Sdf::from_mesh(&p, &t, cell),
            Err(Error::InvalidParameter { name: "cell", .. })
        ));
    }
    // Cells absurdly small for the mesh: counted in f64, refused before
    // allocating (the counting allocator sees nothing large: the test would
    // abort on a multi-terabyte request otherwise).
    for (scale, cell) in [
        (1.0, 1e-5),
        (1.0, 1e-30),
        (1e30, 1.0),
        (1e-3, f32::MIN_POSITIVE),
    ] {
        let q: Vec<Vec3> = p.iter().map(|v| *v * scale).collect();
        match Sdf::from_mesh(&q, &t, cell) {
            Err(Error::GridTooLarge { cells, max }) => {
                assert_eq!(max, MAX_SDF_CELLS);
                assert!(cells > MAX_SDF_CELLS);
            }
            other => panic!("{scale} {cell}: {other:?}"),
        }
    }
    // Coordinates near the float range: refused or built, never a panic or
    // a hang.
    let q: Vec<Vec3> = p.iter().map(|v| *v * 3e38).collect();
    let _ = Sdf::from_mesh(&q, &t, 1e37);
    let _ = Sdf::from_mesh(&q, &t, f32::MAX);
    let e = Error::GridTooLarge { cells: 9, max: 8 }.to_string();
    assert!(e.contains('9') && e.contains('8'), "{e}");
}

#[test]
fn degenerate_triangles_are_tolerated() {
    let (mut p, mut t) = tetra();
    // A zero-area sliver on an edge, a triangle collapsed to a point, and a
    // mesh made of a degenerate triangle alone.
    p.push(Vec3::new(0.05, 0.0, 0.0));
    t.push([0, 1, 4]);
    t.push([2, 2, 2]);
    let sdf = Sdf::from_mesh(&p, &t, 0.005).unwrap();
    assert!(sdf.distance(Vec3::splat(0.02)) < 0.0);
    assert!(sdf.distance(Vec3::splat(-0.02)) > 0.0);
    let line = Sdf::from_mesh(&p, &[[0, 1, 4]], 0.005).unwrap();
    let d = line.distance(Vec3::new(0.05, 0.01, 0.0));
    assert!((d - 0.01).abs() < 1e-3, "{d}");
    let point = Sdf::from_mesh(&p, &[[3, 3, 3]], 0.01).unwrap();
    assert!(point.distance(Vec3::new(0.0, 0.0, 0.1)) >= 0.0);
}

#[test]
fn far_and_nan_points_are_harmless() {
    let m = icosphere(2, 0.1);
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.01).unwrap();
    for far in [1.0f32, 1e3, 1e6, 1e20, 1e30] {
        for dir in [Vec3::X, -Vec3::Y, Vec3::new(1.0, -2.0, 3.0).normalize()] {
            let (d, n) = sdf.distance_and_normal(dir * far);
            assert!(d > 0.0 && d.is_finite(), "{far}: {d}");
            assert!(d >= 0.5 * (far - 0.1), "{far}: {d}");
            assert!(n.dot(dir) > 0.9, "{far}: {n}");
        }
    }
    for p in [
        Vec3::NAN,
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(0.0, 0.0, f32::NAN),
        Vec3::new(0.0, f32::INFINITY, 0.0),
    ] {
        let (d, _) = sdf.distance_and_gradient(p);
        assert!(d.is_nan() || d.is_finite(), "{p}: {d}");
    }
}

#[test]
fn transform_moves_the_field_rigidly() {
    let m = icosphere(3, 0.1);
    let mut sdf = Sdf::from_mesh(&m.0, &m.1, 0.005).unwrap();
    let fixed = sdf.clone();
    assert_eq!(sdf.transform(), Affine3A::IDENTITY);
    let t = Affine3A::from_rotation_translation(
        Quat::from_axis_angle(Vec3::new(0.3, -1.0, 0.5).normalize(), 1.1),
        Vec3::new(0.4, 1.6, -0.2),
    );
    sdf.set_transform(t).unwrap();
    assert_eq!(sdf.transform(), t);
    let mut rng = Rng(5);
    for _ in 0..2000 {
        let p = Vec3::new(
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
        );
        let (d0, g0) = fixed.distance_and_gradient(p);
        let (d1, g1) = sdf.distance_and_gradient(t.transform_point3(p));
        assert!((d0 - d1).abs() <= 2e-6, "{p}: {d0} {d1}");
        let g0w = t.transform_vector3(g0);
        assert!(
            (g0w - g1).length() <= 1e-3 * g0.length().max(1.0),
            "{p}: {g0w} {g1}"
        );
        assert!((sdf.distance(t.transform_point3(p)) - d1).abs() == 0.0);
    }
    // Refusals change nothing.
    let probe = t.transform_point3(Vec3::new(0.05, 0.02, -0.03));
    let before = sdf.distance(probe);
    let bad = [
        Affine3A::from_scale(Vec3::splat(1.01)),
        Affine3A::from_scale(Vec3::new(1.0, 1.0, -1.0)),
        Affine3A::from_cols(
            Vec3::X.into(),
            Vec3::new(0.1, 1.0, 0.0).into(),
            Vec3::Z.into(),
            Vec3::ZERO.into(),
        ),
        Affine3A::from_translation(Vec3::new(f32::NAN, 0.0, 0.0)),
        Affine3A::from_translation(Vec3::new(0.0, f32::INFINITY, 0.0)),
        Affine3A::from_rotation_x(f32::NAN),
        Affine3A::from_scale(Vec3::ZERO),
    ];
    for b in bad {
        assert!(
            matches!(sdf.set_transform(b), Err(Error::InvalidTransform { .. })),
            "{b:?}"
        );
        assert_eq!(sdf.transform(), t);
        assert_eq!(sdf.distance(probe), before);
    }
}

#[test]
fn accessors_describe_the_grid() {
    let m = icosphere(2, 0.1);
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.01).unwrap();
    assert_eq!(sdf.cell(), 0.01);
    let (lo, hi) = sdf.bounds();
    let d = sdf.dims();
    assert_eq!(sdf.node_count(), (d.x * d.y * d.z) as usize);
    assert!(((hi - lo) / 0.01 - (d - 1).as_vec3()).abs().max_element() < 1e-3);
    // The margin: at least MARGIN_CELLS empty cells round the mesh's box.
    let margin = coif_kernels::MARGIN_CELLS as f32 * 0.01;
    assert!(
        (lo + Vec3::splat(margin))
            .cmple(Vec3::splat(-0.1 + 1e-4))
            .all(),
        "{lo}"
    );
    assert!(
        (hi - Vec3::splat(margin))
            .cmpge(Vec3::splat(0.1 - 1e-4))
            .all(),
        "{hi}"
    );
    // Node values are the field at the nodes.
    let v = sdf.node_value(d.x / 2, d.y / 2, d.z / 2).unwrap();
    let p = lo + (d / 2).as_vec3() * 0.01;
    assert_eq!(sdf.distance(p), v);
    assert!(sdf.node_value(d.x, 0, 0).is_none());
}

#[test]
fn lookups_allocate_nothing() {
    let m = icosphere(2, 0.1);
    let mut sdf = Sdf::from_mesh(&m.0, &m.1, 0.01).unwrap();
    sdf.set_transform(Affine3A::from_translation(Vec3::Y))
        .unwrap();
    let mut rng = Rng(3);
    let pts: Vec<Vec3> = (0..10_000)
        .map(|_| Vec3::new(rng.range(-1., 1.), rng.range(0., 2.), rng.range(-1., 1.)))
        .collect();
    let before = coif_testkit::counting::allocations();
    let mut s = 0.0;
    for &p in &pts {
        s += sdf.distance(p) + sdf.distance_and_normal(p).1.x + sdf.gradient(p).y;
    }
    assert_eq!(coif_testkit::counting::allocations() - before, 0);
    assert!(s.is_finite());
}

/// The public SIMD lookup (`sample_mesh_simd`) equals the scalar one
/// (`sample_mesh`) lane by lane, bit for bit, on the bust's field (or the
/// icosphere's when the bust is absent): points inside the box, outside it,
/// and exactly on its faces.
#[test]
fn simd_lookup_equals_scalar_on_a_real_field() {
    let m = coif_testkit::sintel_bust().unwrap_or_else(|| icosphere(4, 0.1));
    let sdf = Sdf::from_mesh(&m.0, &m.1, 0.004).unwrap();
    let (lo, hi) = sdf.bounds();
    let mut rng = Rng(21);
    for k in 0..1000 {
        let mut v = coif_kernels::Vec3Lanes::ZERO;
        let mut pts = [Vec3::ZERO; 8];
        for (l, p) in pts.iter_mut().enumerate() {
            let t = Vec3::new(rng.f(), rng.f(), rng.f());
            *p = match (k + l) % 3 {
                0 => lo + (hi - lo) * t,
                1 => lo + (hi - lo) * (t * 1.6 - Vec3::splat(0.3)),
                _ => {
                    let mut q = lo + (hi - lo) * t;
                    let a = (rng.f() * 3.0) as usize % 3;
                    q[a] = if rng.f() < 0.5 { lo[a] } else { hi[a] };
                    q
                }
            };
            v.set_lane(l, *p);
        }
        let (d8, g8) = sdf.sample_mesh_simd(v);
        for (l, p) in pts.iter().enumerate() {
            let (d, g) = sdf.sample_mesh(*p);
            assert_eq!(d8.as_array()[l].to_bits(), d.to_bits(), "{p}");
            let gl = g8.lane(l);
            assert_eq!(
                [gl.x.to_bits(), gl.y.to_bits(), gl.z.to_bits()],
                [g.x.to_bits(), g.y.to_bits(), g.z.to_bits()],
                "{p}"
            );
            assert_eq!(sdf.distance(*p).to_bits(), d.to_bits());
        }
    }
}
