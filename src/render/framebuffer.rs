//! Linear-RGB float colour and depth per pixel.

use glam::Vec3;

/// `width * height` pixels, row after row from the top. Colour is linear
/// RGB radiance (tone-mapped only on output); depth is the view depth of the
/// nearest opaque surface (the head), `f32::INFINITY` where there is none.
#[derive(Clone, Debug)]
pub struct Framebuffer {
    width: usize,
    height: usize,
    pub color: Vec<Vec3>,
    pub depth: Vec<f32>,
}

impl Framebuffer {
    /// Allocates the buffers once.
    pub fn new(width: usize, height: usize) -> Framebuffer {
        let (width, height) = (width.max(1), height.max(1));
        Framebuffer {
            width,
            height,
            color: vec![Vec3::ZERO; width * height],
            depth: vec![f32::INFINITY; width * height],
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Fills the colour with a vertical gradient from `top` to `bottom`
    /// and clears the depth.
    pub fn clear_gradient(&mut self, top: Vec3, bottom: Vec3) {
        for (j, row) in self.color.chunks_exact_mut(self.width).enumerate() {
            let s = (j as f32 + 0.5) / self.height as f32;
            row.fill(top.lerp(bottom, s));
        }
        self.depth.fill(f32::INFINITY);
    }

    #[inline]
    pub fn index(&self, x: usize, y: usize) -> usize {
        y * self.width + x
    }
}
