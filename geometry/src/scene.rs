//! Built-in scenes that need no files: hair grown on a sphere "head" (for
//! the default run, tests and benchmarks), single test strands, collision
//! rigs, and a sphere fitted to an authored groom's roots (a stand-in head
//! for grooms that come without one).

use crate::grow::{grow, Growth, InvalidGrowth};
use coif_base::Sphere;
use glam::Vec3;

/// A sphere head with guide strands grown along its normals.
#[derive(Clone, Debug)]
pub struct SphereHead {
    /// The head (and the first sphere of the collision rig).
    pub head: Sphere,
    /// `strand_count * verts_per_strand` points, strand after strand, root first.
    pub points: Vec<Vec3>,
    /// Points per strand.
    pub verts_per_strand: usize,
}

/// Options for [`grow_on_sphere`]: where the roots are (the sphere cap)
/// and how the strands grow from them ([`GrowOptions::growth`]).
#[derive(Clone, Debug)]
pub struct GrowOptions {
    /// Number of strands (roots).
    pub strand_count: usize,
    /// Points per strand, root first.
    pub verts_per_strand: usize,
    /// Strand length in metres.
    pub length: f32,
    /// Head centre in metres.
    pub center: Vec3,
    /// Head radius in metres.
    pub radius: f32,
    /// Roots cover the cap of the sphere above this height, as a fraction of
    /// the radius from the centre (-1 = whole sphere, 0 = upper half).
    pub lowest_root: f32,
    /// Curl amplitude as a fraction of the segment length (0 = straight).
    pub curl: f32,
    /// Seed of the curl's random phases and turns.
    pub seed: u64,
}

/// Most strands [`GrowOptions::validate`] accepts.
pub const MAX_GROWN_STRANDS: usize = 1 << 20;

impl GrowOptions {
    /// The options' ranges: at most [`MAX_GROWN_STRANDS`] strands, a finite
    /// head of positive radius, a lowest root in [-1, 1], and the growth's
    /// own ([`Growth::validate`]).
    pub fn validate(&self) -> Result<(), InvalidGrowth> {
        if self.strand_count > MAX_GROWN_STRANDS {
            return Err(InvalidGrowth("at most 2^20 strands"));
        }
        if !(self.center.is_finite() && self.radius.is_finite() && self.radius > 0.0) {
            return Err(InvalidGrowth("a finite head of radius > 0"));
        }
        if !(-1.0..=1.0).contains(&self.lowest_root) {
            return Err(InvalidGrowth("lowest root in [-1, 1]"));
        }
        self.growth().validate()
    }

    /// The strand growth part of the options, for [`grow`].
    pub fn growth(&self) -> Growth {
        Growth {
            length: self.length,
            verts_per_strand: self.verts_per_strand,
            curl: self.curl,
            seed: self.seed,
        }
    }
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            strand_count: 2048,
            verts_per_strand: 32,
            length: 0.25,
            center: Vec3::ZERO,
            radius: 0.1,
            lowest_root: -0.25,
            curl: 0.0,
            seed: 1,
        }
    }
}

/// Grows strands on a sphere head: roots on a Fibonacci spiral over the cap
/// above `lowest_root` ([`fibonacci_cap`]), each strand grown by [`grow`]
/// straight out along its radial normal (with optional curl around it), so
/// under gravity it falls and drapes.
pub fn grow_on_sphere(o: &GrowOptions) -> SphereHead {
    let (roots, normals) = fibonacci_cap(o.center, o.radius, o.strand_count, o.lowest_root);
    let growth = o.growth();
    SphereHead {
        head: Sphere {
            center: o.center,
            radius: o.radius,
        },
        points: grow(&roots, &normals, &growth),
        verts_per_strand: growth.verts_per_strand.max(2),
    }
}

/// `count` roots and their unit radial normals on a Fibonacci (golden-angle)
/// spiral over the cap of the sphere above height `lowest` (a fraction of
/// the radius from the centre, -1 = whole sphere): root i at height
/// `y_i = 1 - (1 - lowest) (i + 1/2) / count` and azimuth `i * pi (3 - sqrt 5)`.
/// Heights uniform in `[lowest, 1]` cover the cap with even area
/// (Archimedes' hat-box theorem), the golden angle spreads them around it
/// (Vogel 1979; Gonzalez 2010, "Measurement of areas on a sphere using
/// Fibonacci and latitude-longitude lattices").
pub fn fibonacci_cap(
    center: Vec3,
    radius: f32,
    count: usize,
    lowest: f32,
) -> (Vec<Vec3>, Vec<Vec3>) {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let normals: Vec<Vec3> = (0..count)
        .map(|i| {
            let y = 1.0 - (1.0 - lowest) * (i as f32 + 0.5) / count as f32;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), y, r * a.sin()).normalize()
        })
        .collect();
    let roots = normals.iter().map(|n| center + *n * radius).collect();
    (roots, normals)
}

/// One strand sticking out horizontally (+x) from a pinned root at `root`.
pub fn horizontal_strand(root: Vec3, length: f32, verts: usize) -> Vec<Vec3> {
    let verts = verts.max(2);
    (0..verts)
        .map(|v| root + Vec3::X * (length * v as f32 / (verts - 1) as f32))
        .collect()
}

/// Spheres of `radius` tangent to the scalp under `count` evenly chosen
/// roots of an authored groom: each centre sits below its root, against the
/// direction of the strand's first segment (hair leaves the scalp along its
/// normal). A stand-in head for grooms that come without one.
/// Strands of fewer than two points have no first segment: none.
pub fn scalp_spheres(points: &[Vec3], verts: usize, count: usize, radius: f32) -> Vec<Sphere> {
    if verts < 2 {
        return Vec::new();
    }
    let strands = points.len() / verts;
    (0..count.min(strands))
        .filter_map(|k| {
            let s = (2 * k + 1) * strands / (2 * count);
            let (root, next) = (points[s * verts], points[s * verts + 1]);
            let normal = (next - root).try_normalize()?;
            Some(Sphere {
                center: root - normal * (radius * 1.02),
                radius,
            })
        })
        .collect()
}

/// A collision rig of `near.len() + far` spheres: the given spheres near the
/// hair, and `far` more (torso, arms, legs, props) a body length below
/// `anchor`, so that the broad phase has many spheres to skip and few to test.
pub fn rig_with_distractors(near: &[Sphere], anchor: Vec3, scale: f32, far: usize) -> Vec<Sphere> {
    let mut rig = near.to_vec();
    for k in 0..far {
        let (i, j, l) = ((k % 7) as f32, ((k / 7) % 6) as f32, (k / 42) as f32);
        let c = anchor
            + Vec3::new(
                (i - 3.0) * 1.5 * scale,
                -6.0 * scale - l * 1.5 * scale,
                (j - 2.5) * 1.5 * scale,
            );
        rig.push(Sphere {
            center: c,
            radius: scale * 0.5,
        });
    }
    rig
}

/// A body rig of `total` spheres around `head`: the head, a neck just below,
/// and distractors a body length away (see [`rig_with_distractors`]).
pub fn body_rig(head: &Sphere, total: usize) -> Vec<Sphere> {
    let neck = Sphere {
        center: head.center - Vec3::Y * (head.radius * 1.6),
        radius: head.radius * 0.55,
    };
    let near = [head.clone(), neck];
    let n = total.min(2);
    rig_with_distractors(&near[..n], head.center, head.radius, total - n)
}

/// Least-squares sphere through `points` (algebraic fit, Coope 1993: solve
/// `|p|^2 = 2 c.p + (r^2 - |c|^2)` for c and r in f64). None for fewer than
/// four points or a degenerate (coplanar/collinear) set. Fitted to a
/// groom's roots it is the head proxy of a groom that comes without a mesh
/// (collisions, the scalp triangles' centre).
///
/// ```
/// use coif_geometry::scene::fit_sphere;
/// use glam::Vec3;
/// // Roots on a cap of a 9 cm head centred at (0, 1.6, 0).
/// let roots: Vec<Vec3> = (0..50)
///     .map(|i| {
///         let (a, y) = (i as f32 * 2.4, 0.3 + 0.7 * (i as f32 / 50.0));
///         let r = (1.0 - y * y).sqrt();
///         Vec3::new(0.0, 1.6, 0.0) + Vec3::new(r * a.cos(), y, r * a.sin()) * 0.09
///     })
///     .collect();
/// let head = fit_sphere(&roots).unwrap();
/// assert!((head.radius - 0.09).abs() < 1e-4);
/// assert!(head.center.distance(Vec3::new(0.0, 1.6, 0.0)) < 1e-4);
/// assert!(fit_sphere(&roots[..3]).is_none());
/// ```
pub fn fit_sphere(points: &[Vec3]) -> Option<Sphere> {
    if points.len() < 4 {
        return None;
    }
    let mean = points.iter().map(|p| p.as_dvec3()).sum::<glam::DVec3>() / points.len() as f64;
    // Normal equations A^T A x = A^T b with rows (2p, 1), b = |p|^2, centred on the mean.
    let mut m = [[0.0f64; 5]; 4];
    for p in points {
        let q = p.as_dvec3() - mean;
        let row = [2.0 * q.x, 2.0 * q.y, 2.0 * q.z, 1.0];
        let b = q.length_squared();
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += row[i] * row[j];
            }
            m[i][4] += row[i] * b;
        }
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..4 {
        let pivot = (col..4).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        m.swap(col, pivot);
        if m[col][col].abs() < 1e-12 * (1.0 + m[0][0].abs()) {
            return None;
        }
        let pivot_row = m[col];
        for (r, row) in m.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot_row[col];
                for (x, p) in row.iter_mut().zip(pivot_row).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    let x: Vec<f64> = (0..4).map(|i| m[i][4] / m[i][i]).collect();
    let c = glam::DVec3::new(x[0], x[1], x[2]);
    let r2 = x[3] + c.length_squared();
    (r2 > 0.0 && r2.is_finite()).then(|| Sphere {
        center: (c + mean).as_vec3(),
        radius: r2.sqrt() as f32,
    })
}
