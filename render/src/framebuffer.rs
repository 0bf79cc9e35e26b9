//! Linear-RGB float colour and depth per pixel.

use glam::Vec3;

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
        for (j, row) in self.pixels.chunks_exact_mut(self.width).enumerate() {
            let s = (j as f32 + 0.5) / self.height as f32;
            row.fill(Pixel {
                color: top.lerp(bottom, s),
                depth: f32::INFINITY,
            });
        }
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
