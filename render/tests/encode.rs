//! The tone map and sRGB encoding in bands of rows as tasks: the same
//! bytes as one pass, on any executor, for any frame size.

use coif_base::tasks::{Executor, Serial, Workers};
use coif_base::SplitMix64;
use coif_render::image::{srgb_encode, tone_map, ENCODE_BAND_ROWS};
use coif_render::{Framebuffer, RgbImage};
use glam::Vec3;

#[test]
fn encoding_in_bands_is_the_same_bytes_as_pixel_by_pixel() {
    let mut rng = SplitMix64::new(7);
    let workers = [Workers::new(2).unwrap(), Workers::new(3).unwrap()];
    let mut executors: Vec<&dyn Executor> = vec![&Serial];
    executors.extend(workers.iter().map(|w| w as &dyn Executor));
    let mut image = RgbImage::new(1, 1);
    // One band, several with a short last one, a single row and column.
    for (w, h) in [(17, 5), (131, 3 * ENCODE_BAND_ROWS + 7), (1, 200), (300, 1)] {
        let mut frame = Framebuffer::new(w, h);
        for p in &mut frame.pixels {
            // Negative, huge and NaN colours as well as ordinary ones.
            let c = |r: &mut SplitMix64| match r.next_u64() % 16 {
                0 => f32::NAN,
                1 => -1.0,
                2 => 1e30,
                _ => 4.0 * r.next_f32(),
            };
            p.color = Vec3::new(c(&mut rng), c(&mut rng), c(&mut rng));
        }
        let exposure = 1.3;
        let want: Vec<u8> = frame
            .pixels
            .iter()
            .flat_map(|p| tone_map(p.color, exposure).to_array())
            .map(|v| (srgb_encode(v) * 255.0 + 0.5) as u8)
            .collect();
        for (k, executor) in executors.iter().enumerate() {
            image.encode_with(&frame, exposure, *executor);
            assert_eq!((image.width, image.height), (w, h));
            assert!(image.data == want, "{w} x {h}, executor {k}: bytes differ");
        }
    }
}
