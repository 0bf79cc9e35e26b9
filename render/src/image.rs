//! Output: tone map, sRGB encoding, contact sheets and PNG files.

use super::Framebuffer;
use coif_base::tasks::{for_each_chunk_mut, Executor, Serial};
use glam::Vec3;
use std::io::Write;

/// Rows per task of [`RgbImage::encode_with`].
pub const ENCODE_BAND_ROWS: usize = 32;

/// An 8-bit sRGB image, RGB interleaved, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `3 * width * height` bytes, R G B per pixel, row after row from the top.
    pub data: Vec<u8>,
}

/// sRGB opto-electronic transfer function (IEC 61966-2-1) of a linear value
/// in `[0, 1]`: `12.92 x` below 0.0031308, else `1.055 x^(1/2.4) - 0.055`.
#[inline]
pub fn srgb_encode(x: f32) -> f32 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Exponential tone map `1 - exp(-exposure x)` per channel: linear for
/// small values, saturating smoothly for highlights.
#[inline]
pub fn tone_map(c: Vec3, exposure: f32) -> Vec3 {
    Vec3::ONE - (-(c * exposure).max(Vec3::ZERO)).exp()
}

impl RgbImage {
    /// A black image.
    pub fn new(width: usize, height: usize) -> RgbImage {
        RgbImage {
            width,
            height,
            data: vec![0; width * height * 3],
        }
    }

    /// Tone-maps and sRGB-encodes `frame` into this image (resized to the
    /// frame if needed).
    pub fn encode(&mut self, frame: &Framebuffer, exposure: f32) {
        self.encode_with(frame, exposure, &Serial);
    }

    /// [`RgbImage::encode`] in bands of [`ENCODE_BAND_ROWS`] rows as tasks
    /// on `executor` (each byte depends on its own pixel alone: the same
    /// bytes with any executor). Allocates only when the size changes.
    pub fn encode_with(&mut self, frame: &Framebuffer, exposure: f32, executor: &dyn Executor) {
        self.width = frame.width();
        self.height = frame.height();
        self.data.resize(self.width * self.height * 3, 0);
        let band = ENCODE_BAND_ROWS * self.width;
        let pixels = &frame.pixels;
        for_each_chunk_mut(executor, &mut self.data, 3 * band, &|b, bytes| {
            for (px, p) in bytes.chunks_exact_mut(3).zip(&pixels[b * band..]) {
                let m = tone_map(p.color, exposure);
                for (dst, v) in px.iter_mut().zip(m.to_array()) {
                    *dst = (srgb_encode(v) * 255.0 + 0.5) as u8;
                }
            }
        });
    }

    /// The tone-mapped sRGB image of `frame` (see [`RgbImage::encode`]).
    pub fn from_frame(frame: &Framebuffer, exposure: f32) -> RgbImage {
        let mut img = RgbImage::new(frame.width(), frame.height());
        img.encode(frame, exposure);
        img
    }

    /// The R, G, B bytes of pixel (x, y).
    pub fn pixel(&self, x: usize, y: usize) -> [u8; 3] {
        let i = 3 * (y * self.width + x);
        [self.data[i], self.data[i + 1], self.data[i + 2]]
    }

    /// Tiles `images` (all of the first one's size) in `columns` columns
    /// with a `gap`-pixel border of `background`.
    pub fn contact_sheet(
        images: &[RgbImage],
        columns: usize,
        gap: usize,
        background: [u8; 3],
    ) -> RgbImage {
        let Some(first) = images.first() else {
            return RgbImage::new(0, 0);
        };
        let columns = columns.clamp(1, images.len());
        let rows = images.len().div_ceil(columns);
        let (tw, th) = (first.width, first.height);
        let width = columns * tw + (columns + 1) * gap;
        let height = rows * th + (rows + 1) * gap;
        let mut sheet = RgbImage::new(width, height);
        for px in sheet.data.chunks_exact_mut(3) {
            px.copy_from_slice(&background);
        }
        for (k, img) in images.iter().enumerate() {
            if img.width != tw || img.height != th {
                continue;
            }
            let (ox, oy) = (
                gap + (k % columns) * (tw + gap),
                gap + (k / columns) * (th + gap),
            );
            for y in 0..th {
                let src = &img.data[3 * y * tw..3 * (y + 1) * tw];
                let start = 3 * ((oy + y) * width + ox);
                sheet.data[start..start + 3 * tw].copy_from_slice(src);
            }
        }
        sheet
    }

    /// PNG bytes (8-bit RGB) into `out`.
    pub fn write_png(&self, out: impl Write) -> Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width as u32, self.height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&self.data)?;
        writer.finish()
    }

    /// Writes a PNG file.
    pub fn save_png(&self, path: &std::path::Path) -> std::io::Result<()> {
        let file = std::io::BufWriter::new(std::fs::File::create(path)?);
        self.write_png(file).map_err(std::io::Error::other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_is_continuous_and_maps_the_ends() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        let a = 0.003_130_8f32;
        assert!((srgb_encode(a) - srgb_encode(a + 1e-7)).abs() < 1e-4);
        assert!((srgb_encode(0.214) - 0.5).abs() < 2e-3, "mid grey");
    }

    #[test]
    fn a_contact_sheet_places_each_tile() {
        let mut a = RgbImage::new(2, 2);
        a.data.fill(10);
        let mut b = RgbImage::new(2, 2);
        b.data.fill(200);
        let s = RgbImage::contact_sheet(&[a, b.clone(), b], 2, 1, [0, 0, 0]);
        assert_eq!((s.width, s.height), (7, 7));
        assert_eq!(s.pixel(1, 1), [10; 3]);
        assert_eq!(s.pixel(4, 2), [200; 3]);
        assert_eq!(s.pixel(1, 4), [200; 3]);
        assert_eq!(s.pixel(4, 4), [0; 3], "empty slot stays background");
        assert_eq!(s.pixel(3, 1), [0; 3], "gap");
    }
}
