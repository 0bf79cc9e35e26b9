//! The ribbons of the demo: they show in the default render, their
//! attached row follows the head exactly, and they stay out of the head.

mod common;

use coif_frame::ribbon::RIBBON_CLEARANCE;
use coif_frame::{motion, FramePipeline, FrameSettings, HairScene};

fn scene() -> HairScene {
    common::small_hair_scene()
}

/// Pixels of the ribbon's colour family: saturated red, red well over
/// twice green and blue (the hair is brown: green is 0.6-0.8 of red; the
/// skin and the background are far from it).
fn red_pixels(data: &[u8]) -> usize {
    data.chunks_exact(3)
        .filter(|p| {
            let (r, g, b) = (p[0] as u32, p[1] as u32, p[2] as u32);
            r > 40 && r > 2 * g && r > 2 * b
        })
        .count()
}

#[test]
fn the_ribbon_shows_in_the_default_render_and_not_without_it() {
    let render = |scene: &HairScene| {
        let mut p = FramePipeline::new(scene, FrameSettings::small(128), 0.5).unwrap();
        let pivot = p.pivot();
        for f in 0..4 {
            p.frame(1.0 / 30.0, motion::turn_and_nod(f as f32 / 30.0, pivot));
        }
        (p.image(), p.stats())
    };
    let with = scene();
    assert_eq!(
        with.ribbons.len(),
        2,
        "the built-in head has a bow's two tails"
    );
    let (image, stats) = render(&with);
    let (bare, bare_stats) = render(&with.clone().without_ribbons());
    let (red, red_bare) = (red_pixels(&image.data), red_pixels(&bare.data));
    // Two 3.5 cm tails, 26-30 cm long, are some 300 px at this size; much
    // of them is in front of the hair.
    eprintln!(
        "red pixels {red} (ribbon pixels {}), without the ribbon {red_bare}",
        stats.ribbon_pixels
    );
    assert!(
        red > 150 && red_bare < 5,
        "red pixels: {red} with the ribbon, {red_bare} without"
    );
    assert!(stats.ribbon_pixels >= red, "{stats:?}");
    assert_eq!(bare_stats.ribbon_pixels, 0);
    // The ribbon's pixels were background, head or hair before: the
    // pictures differ in at least as many pixels as are red.
    let differ = image
        .data
        .chunks_exact(3)
        .zip(bare.data.chunks_exact(3))
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ >= red, "{differ} pixels differ");
}

#[test]
fn the_attached_row_follows_the_head_and_the_ribbon_stays_out_of_it() {
    // The default motion (3 s at 30 fps, then half a second at rest),
    // simulated frame by frame as the binary does.
    let scene = scene();
    let head = scene.head[0].clone();
    // Settled 1.5 s like the binary (FrameSettings::small differs from the
    // default in rendering settings only).
    let mut p = FramePipeline::new(&scene, FrameSettings::small(64), 1.5).unwrap();
    let pivot = p.pivot();
    let ribbons = p.ribbons().len();
    assert_eq!(ribbons, 2);
    let mut deepest = f32::INFINITY; // smallest distance from the head's surface
    let mut tip_travel = 0f32;
    for f in 0..105 {
        let pose = motion::turn_and_nod(f as f32 / 30.0, pivot);
        p.simulate(1.0 / 30.0, pose);
        let centre = pose.transform_point3(head.center);
        for i in 0..ribbons {
            let stage = p.ribbons();
            let (rows, cols) = stage.grid(i);
            let (blended, skinned) = (stage.blended(i), stage.skinned(i));
            let rest = &scene.ribbons[i];
            for k in 0..rows * cols {
                if rest.weights[k] == 0.0 {
                    // Weight 0: the skinned point, bit for bit, and that is
                    // the head pose applied to the rest point.
                    assert_eq!(blended[k], skinned[k], "frame {f} ribbon {i} point {k}");
                    let expected = pose.transform_point3(rest.points[k]);
                    assert!(
                        blended[k].distance(expected) < 1e-5,
                        "frame {f}: {} vs {expected}",
                        blended[k]
                    );
                }
                deepest = deepest.min(blended[k].distance(centre) - head.radius);
            }
            // Quad centres too (the triangles between the particles).
            for r in 0..rows - 1 {
                for c in 0..cols - 1 {
                    let k = r * cols + c;
                    let mid = 0.25
                        * (blended[k] + blended[k + 1] + blended[k + cols] + blended[k + cols + 1]);
                    deepest = deepest.min(mid.distance(centre) - head.radius);
                }
            }
            let tip = blended[rows * cols - cols / 2];
            let tip_skinned = skinned[rows * cols - cols / 2];
            tip_travel = tip_travel.max(tip.distance(tip_skinned));
            assert!(blended.iter().all(|q| q.is_finite()));
        }
    }
    eprintln!(
        "closest approach to the head surface {:.2} mm, tip off its skin up to {:.1} cm",
        deepest * 1e3,
        tip_travel * 1e2
    );
    assert!(
        deepest > -1e-3,
        "a ribbon point went {:.2} mm into the head",
        -deepest * 1e3
    );
    // And out of the sphere it collides with (the head grown by the hair
    // layer it lies on), to within a millimetre too.
    assert!(
        deepest - RIBBON_CLEARANCE > -1e-3,
        "a ribbon point went {:.2} mm into the grown head",
        (RIBBON_CLEARANCE - deepest) * 1e3
    );
    // It swings: the tip leaves its rigidly skinned place by centimetres.
    assert!(
        tip_travel > 0.02,
        "the tip moved {tip_travel} m off its skin"
    );
}
