//! Linear-RGB float colour and depth per pixel.

use coif_base::tasks::{for_each_chunk_mut, Executor, Serial};
use glam::Vec3;

/// Rows per task of [`Framebuffer::clear_gradient_with`]: 64 rows of a
/// 512-pixel frame are 512 KiB written, about a tenth of a millisecond.
const CLEAR_BAND_ROWS: usize = 64;

/// One pixel: colour and depth side by side (16 bytes), so blending a hair
/// fragment touches one cache line, not two.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Pixel {
    /// Linear RGB radiance (tone-mapped only on output).
    pub color: Vec3,
    /// View depth of the nearest opaque surface (the head),
    /// `f32::INFINITY` where there is none.
    pub depth: f32,
}

/// `width * height` pixels, row after row from the top.
#[derive(Clone, Debug)]
pub struct Framebuffer {
    width: usize,
    height: usize,
    /// Pixels row after row, from the top.
    pub pixels: Vec<Pixel>,
}

impl Framebuffer {
    /// Allocates the buffers once.
    pub fn new(width: usize, height: usize) -> Framebuffer {
        let (width, height) = (width.max(1), height.max(1));
        Framebuffer {
            width,
            height,
            pixels: vec![
                Pixel {
                    color: Vec3::ZERO,
                    depth: f32::INFINITY,
                };
                width * height
            ],
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Fills the colour with a vertical gradient from `top` to `bottom`
    /// and clears the depth.
    pub fn clear_gradient(&mut self, top: Vec3, bottom: Vec3) {
        self.clear_gradient_with(top, bottom, &Serial);
    }

    /// [`Framebuffer::clear_gradient`] in bands of 64 rows
    /// as tasks on `executor` (each row's colour depends on its number
    /// alone: the same bytes with any executor).
    pub fn clear_gradient_with(&mut self, top: Vec3, bottom: Vec3, executor: &dyn Executor) {
        let (width, height) = (self.width, self.height);
        let band = CLEAR_BAND_ROWS * width;
        for_each_chunk_mut(executor, &mut self.pixels, band, &|b, rows| {
            for (r, row) in rows.chunks_exact_mut(width).enumerate() {
                let j = b * CLEAR_BAND_ROWS + r;
                let s = (j as f32 + 0.5) / height as f32;
                row.fill(Pixel {
                    color: top.lerp(bottom, s),
                    depth: f32::INFINITY,
                });
            }
        });
    }

    /// Index of pixel (x, y) in [`Framebuffer::pixels`].
    #[inline]
    pub fn index(&self, x: usize, y: usize) -> usize {
        y * self.width + x
    }

    /// Colour of pixel index `i` (see [`Framebuffer::index`]).
    #[inline]
    pub fn color(&self, i: usize) -> Vec3 {
        self.pixels[i].color
    }

    /// Depth of pixel index `i`.
    #[inline]
    pub fn depth(&self, i: usize) -> f32 {
        self.pixels[i].depth
    }
}
