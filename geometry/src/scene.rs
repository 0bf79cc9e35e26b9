//! Built-in scenes: hair grown on a sphere "head", for the default run,
//! tests and benchmarks, with no files needed.

use coif_base::Sphere;
use coif_base::SplitMix64;
use glam::Vec3;

/// A sphere head with guide strands grown along its normals.
#[derive(Clone, Debug)]
pub struct SphereHead {
    /// The head (and the first sphere of the collision rig).
    pub head: Sphere,
    /// `strand_count * verts_per_strand` points, strand after strand, root first.
    pub points: Vec<Vec3>,
    pub verts_per_strand: usize,
}

/// Options for [`grow_on_sphere`].
#[derive(Clone, Debug)]
pub struct GrowOptions {
    pub strand_count: usize,
    pub verts_per_strand: usize,
    /// Strand length in metres.
    pub length: f32,
    /// Head centre and radius in metres.
    pub center: Vec3,
    pub radius: f32,
    /// Roots cover the cap of the sphere above this height, as a fraction of
    /// the radius from the centre (-1 = whole sphere, 0 = upper half).
    pub lowest_root: f32,
    /// Curl amplitude as a fraction of the segment length (0 = straight).
    pub curl: f32,
    pub seed: u64,
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

/// Hair grown on the default sphere head ([`grow_on_sphere`], curl 0.3) and
/// draped under gravity for `steps` steps of the default simulation: the
/// draped head the shadow-map tests, bench, report and profiling harness
/// measure on. Returns the world positions and the vertices per strand.
pub fn draped_on_sphere(strands: usize, verts: usize, steps: usize) -> (Vec<Vec3>, usize) {
    let scene = grow_on_sphere(&GrowOptions {
        strand_count: strands,
        verts_per_strand: verts,
        curl: 0.3,
        ..Default::default()
    });
    let rig = [scene.head.clone()];
    let params = coif_kernels::SimParams::default();
    let mut s = coif_kernels::Strands::from_polylines(&scene.points, scene.verts_per_strand)
        .expect("grown hair is valid");
    for _ in 0..steps {
        coif_kernels::step(&mut s, &params, &rig);
    }
    (s.positions(), scene.verts_per_strand)
}

/// Grows strands along the normals of a sphere: roots on a Fibonacci spiral
/// over the cap above `lowest_root`, each strand leaving straight along its
/// normal (with optional curl around it), so under gravity it falls and drapes.
pub fn grow_on_sphere(o: &GrowOptions) -> SphereHead {
    let mut rng = SplitMix64::new(o.seed);
    let verts = o.verts_per_strand.max(2);
    let seg = o.length / (verts - 1) as f32;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let mut points = Vec::with_capacity(o.strand_count * verts);
    for i in 0..o.strand_count {
        // Heights uniform in [lowest_root, 1] cover the cap with even area.
        let y = 1.0 - (1.0 - o.lowest_root) * (i as f32 + 0.5) / o.strand_count as f32;
        let r = (1.0 - y * y).max(0.0).sqrt();
        let a = golden * i as f32;
        let n = Vec3::new(r * a.cos(), y, r * a.sin()).normalize();
        grow_strand(
            o.center + n * o.radius,
            n,
            seg,
            verts,
            o.curl,
            &mut rng,
            &mut points,
        );
    }
    SphereHead {
        head: Sphere {
            center: o.center,
            radius: o.radius,
        },
        points,
        verts_per_strand: verts,
    }
}

/// Appends one strand of `verts` points `seg` apart growing from `root`
/// along the unit `normal`, curling around it: a helix of 2-4 random turns
/// with a random phase, of radius `curl * seg`, growing in over the first
/// fifth of the strand.
pub fn grow_strand(
    root: Vec3,
    normal: Vec3,
    seg: f32,
    verts: usize,
    curl: f32,
    rng: &mut SplitMix64,
    out: &mut Vec<Vec3>,
) {
    let (u, w) = normal.any_orthonormal_pair();
    let phase = rng.range(0.0, std::f32::consts::TAU);
    let turns = rng.range(2.0, 4.0);
    for v in 0..verts {
        let s = v as f32 / (verts.max(2) - 1) as f32;
        let angle = phase + turns * std::f32::consts::TAU * s;
        let around = (u * angle.cos() + w * angle.sin()) * (curl * seg * s.min(0.2) * 5.0);
        out.push(root + normal * (seg * v as f32) + around);
    }
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
pub fn scalp_spheres(points: &[Vec3], verts: usize, count: usize, radius: f32) -> Vec<Sphere> {
    let strands = points.len().checked_div(verts).unwrap_or(0);
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
/// four points or a degenerate (coplanar/collinear) set.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_a_sphere_to_points_on_a_cap() {
        let h = grow_on_sphere(&GrowOptions {
            center: Vec3::new(0.3, 1.6, -0.2),
            radius: 0.09,
            ..Default::default()
        });
        let roots: Vec<Vec3> = h.points.iter().step_by(32).copied().collect();
        let s = fit_sphere(&roots).unwrap();
        assert!(
            (s.center - Vec3::new(0.3, 1.6, -0.2)).length() < 1e-4,
            "{:?}",
            s
        );
        assert!((s.radius - 0.09).abs() < 1e-4);
        assert!(fit_sphere(&roots[..3]).is_none());
        let flat: Vec<Vec3> = (0..20)
            .map(|i| Vec3::new(i as f32, (i * i) as f32, 0.0))
            .collect();
        assert!(
            fit_sphere(&flat).is_none(),
            "coplanar points have no unique sphere"
        );
    }

    #[test]
    fn strands_start_on_the_sphere_and_have_the_asked_length() {
        let o = GrowOptions {
            strand_count: 100,
            curl: 0.0,
            ..Default::default()
        };
        let h = grow_on_sphere(&o);
        assert_eq!(h.points.len(), 100 * 32);
        for s in h.points.chunks(32) {
            assert!(((s[0] - o.center).length() - o.radius).abs() < 1e-5);
            let len: f32 = s.windows(2).map(|w| (w[1] - w[0]).length()).sum();
            assert!((len - o.length).abs() < 1e-4, "{len}");
            assert!(s[0].y >= o.lowest_root * o.radius - 1e-5);
        }
    }
}
