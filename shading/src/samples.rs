//! Shading sample batches in structure-of-arrays form, and their RGB output.
//!
//! Every batch shading path (Kajiya-Kay, Marschner tables, pbrt tables) reads
//! a [`ShadingSamples`] and writes an [`RgbBuffer`] that the caller owns and
//! reuses frame after frame: `clear` + `push` (or
//! [`ShadingSamples::columns_mut`]) never reallocate once the capacity has
//! been reached.
//!
//! The nine arrays of a [`ShadingSamples`] are private so that they always
//! have one length: every way to fill them (`push`, `set`, `columns_mut`,
//! the validated `from_columns`) keeps them equal, and every batch path can
//! trust it.

use crate::Error;
use coif_base::lanes::F32Lanes;
use coif_base::{Vec3Lanes, LANES};
use glam::Vec3;

/// Per-sample unit tangent `t` (root to tip), unit direction toward the
/// light `wi` and unit direction toward the viewer `wo`, one array per
/// component so that eight samples load as three `F32Lanes` registers. The
/// nine arrays always have the same length (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct ShadingSamples {
    /// Tangents, one array per coordinate.
    t: [Vec<f32>; 3],
    /// Directions toward the light, one array per coordinate.
    wi: [Vec<f32>; 3],
    /// Directions toward the viewer, one array per coordinate.
    wo: [Vec<f32>; 3],
}

/// Mutable views of the nine arrays of a [`ShadingSamples`], all of the
/// same length (from [`ShadingSamples::columns_mut`]): fill them column by
/// column.
#[derive(Debug)]
pub struct SampleColumns<'a> {
    /// Tangents, one slice per coordinate.
    pub t: [&'a mut [f32]; 3],
    /// Directions toward the light, one slice per coordinate.
    pub wi: [&'a mut [f32]; 3],
    /// Directions toward the viewer, one slice per coordinate.
    pub wo: [&'a mut [f32]; 3],
}

impl ShadingSamples {
    /// Samples from nine arrays (`t`, `wi`, `wo`, one array per coordinate),
    /// taken as they are.
    ///
    /// # Errors
    ///
    /// [`Error::CountMismatch`] if the nine arrays are not all as long as
    /// `t[0]`.
    pub fn from_columns(
        t: [Vec<f32>; 3],
        wi: [Vec<f32>; 3],
        wo: [Vec<f32>; 3],
    ) -> Result<ShadingSamples, Error> {
        let n = t[0].len();
        for (what, arrays) in [("t", &t), ("wi", &wi), ("wo", &wo)] {
            if let Some(a) = arrays.iter().find(|a| a.len() != n) {
                return Err(Error::CountMismatch {
                    what,
                    expected: n,
                    got: a.len(),
                });
            }
        }
        Ok(ShadingSamples { t, wi, wo })
    }

    /// Tangents, one slice per coordinate (each `len()` long).
    pub fn t(&self) -> [&[f32]; 3] {
        self.t.each_ref().map(Vec::as_slice)
    }

    /// Directions toward the light, one slice per coordinate.
    pub fn wi(&self) -> [&[f32]; 3] {
        self.wi.each_ref().map(Vec::as_slice)
    }

    /// Directions toward the viewer, one slice per coordinate.
    pub fn wo(&self) -> [&[f32]; 3] {
        self.wo.each_ref().map(Vec::as_slice)
    }

    /// Resizes the batch to `n` samples (new ones zero, allocating only past
    /// the capacity) and returns its nine arrays to fill column by column.
    pub fn columns_mut(&mut self, n: usize) -> SampleColumns<'_> {
        for a in self
            .t
            .iter_mut()
            .chain(self.wi.iter_mut())
            .chain(self.wo.iter_mut())
        {
            a.resize(n, 0.0);
        }
        SampleColumns {
            t: self.t.each_mut().map(Vec::as_mut_slice),
            wi: self.wi.each_mut().map(Vec::as_mut_slice),
            wo: self.wo.each_mut().map(Vec::as_mut_slice),
        }
    }

    /// Empty, with room for `n` samples.
    ///
    /// # Panics
    ///
    /// Only as `Vec::with_capacity` does, if `n` floats cannot be allocated.
    pub fn with_capacity(n: usize) -> Self {
        let v = || {
            [
                Vec::with_capacity(n),
                Vec::with_capacity(n),
                Vec::with_capacity(n),
            ]
        };
        ShadingSamples {
            t: v(),
            wi: v(),
            wo: v(),
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t[0].len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Empties the batch, keeping its capacity.
    pub fn clear(&mut self) {
        for a in self
            .t
            .iter_mut()
            .chain(self.wi.iter_mut())
            .chain(self.wo.iter_mut())
        {
            a.clear();
        }
    }

    /// Appends one sample.
    pub fn push(&mut self, t: Vec3, wi: Vec3, wo: Vec3) {
        for (dst, v) in [(&mut self.t, t), (&mut self.wi, wi), (&mut self.wo, wo)] {
            dst[0].push(v.x);
            dst[1].push(v.y);
            dst[2].push(v.z);
        }
    }

    /// Sample `i` as (t, wi, wo).
    ///
    /// # Panics
    ///
    /// If `i >= len()` (as slice indexing does); see
    /// [`ShadingSamples::try_get`].
    pub fn get(&self, i: usize) -> (Vec3, Vec3, Vec3) {
        let g = |a: &[Vec<f32>; 3]| Vec3::new(a[0][i], a[1][i], a[2][i]);
        (g(&self.t), g(&self.wi), g(&self.wo))
    }

    /// Sample `i` as (t, wi, wo), or `None` if `i >= len()`.
    pub fn try_get(&self, i: usize) -> Option<(Vec3, Vec3, Vec3)> {
        (i < self.len()).then(|| self.get(i))
    }

    /// Replaces sample `i`.
    ///
    /// # Errors
    ///
    /// [`Error::IndexOutOfRange`] (and nothing changed) if `i >= len()`.
    pub fn set(&mut self, i: usize, t: Vec3, wi: Vec3, wo: Vec3) -> Result<(), Error> {
        if i >= self.len() {
            return Err(Error::IndexOutOfRange {
                index: i,
                len: self.len(),
            });
        }
        for (dst, v) in [(&mut self.t, t), (&mut self.wi, wi), (&mut self.wo, wo)] {
            dst[0][i] = v.x;
            dst[1][i] = v.y;
            dst[2][i] = v.z;
        }
        Ok(())
    }

    /// Samples `start .. start + LANES` as lanes (t, wi, wo). Lanes past the
    /// end are padded with a harmless valid configuration (t = x, wi = wo = y)
    /// so that padding never produces NaN (a `start` past the end gives
    /// padding only).
    #[inline]
    pub fn load_block(&self, start: usize) -> (Vec3Lanes, Vec3Lanes, Vec3Lanes) {
        let n = self.len();
        let load = |a: &[Vec<f32>; 3], pad: Vec3| {
            let one = |c: &Vec<f32>, p: f32| {
                if n >= LANES && start <= n - LANES {
                    F32Lanes::new(c[start..start + LANES].try_into().expect("LANES values"))
                } else {
                    coif_base::lanes::load_padded(&c[start.min(n)..n], p)
                }
            };
            Vec3Lanes::new(one(&a[0], pad.x), one(&a[1], pad.y), one(&a[2], pad.z))
        };
        (
            load(&self.t, Vec3::X),
            load(&self.wi, Vec3::Y),
            load(&self.wo, Vec3::Y),
        )
    }
}

/// Caller-owned RGB output, one array per channel. Every batch path resizes
/// all three channels to its sample count before writing, so channels of
/// unequal length (the fields are public) are harmless there.
#[derive(Clone, Debug, Default)]
pub struct RgbBuffer {
    /// Red channel, one value per sample.
    pub r: Vec<f32>,
    /// Green channel, one value per sample.
    pub g: Vec<f32>,
    /// Blue channel, one value per sample.
    pub b: Vec<f32>,
}

impl RgbBuffer {
    /// A buffer of `n` zeros.
    ///
    /// # Panics
    ///
    /// Only as an allocation does, if `n` floats cannot be allocated.
    pub fn zeros(n: usize) -> Self {
        RgbBuffer {
            r: vec![0.0; n],
            g: vec![0.0; n],
            b: vec![0.0; n],
        }
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// Whether the buffer is empty.
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Resizes to `n` samples (allocates only when growing past capacity).
    pub fn resize(&mut self, n: usize) {
        self.r.resize(n, 0.0);
        self.g.resize(n, 0.0);
        self.b.resize(n, 0.0);
    }

    /// Value `i` as RGB.
    ///
    /// # Panics
    ///
    /// If `i` is out of range of a channel (as slice indexing does).
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.r[i], self.g[i], self.b[i])
    }

    /// Sets value `i`.
    ///
    /// # Panics
    ///
    /// If `i` is out of range of a channel (as slice indexing does).
    pub fn set(&mut self, i: usize, v: Vec3) {
        self.r[i] = v.x;
        self.g[i] = v.y;
        self.b[i] = v.z;
    }

    /// [`RgbBuffer::get`], or `None` if `i` is out of range of a channel.
    pub fn try_get(&self, i: usize) -> Option<Vec3> {
        Some(Vec3::new(*self.r.get(i)?, *self.g.get(i)?, *self.b.get(i)?))
    }

    /// [`RgbBuffer::set`], or `Error::IndexOutOfRange` (nothing changed)
    /// if `i` is out of range of a channel.
    pub fn try_set(&mut self, i: usize, v: Vec3) -> Result<(), crate::Error> {
        let len = self.r.len().min(self.g.len()).min(self.b.len());
        if i >= len {
            return Err(crate::Error::IndexOutOfRange { index: i, len });
        }
        self.set(i, v);
        Ok(())
    }

    /// Samples `start ..` in lanes, zeros past the end (of the shortest
    /// channel, should the public channels differ in length).
    #[inline]
    pub fn load_block(&self, start: usize) -> Vec3Lanes {
        let len = self.r.len().min(self.g.len()).min(self.b.len());
        let n = len.saturating_sub(start).min(LANES);
        let lanes = |c: &[f32]| {
            let mut v = [0.0f32; LANES];
            if n > 0 {
                v[..n].copy_from_slice(&c[start..start + n]);
            }
            F32Lanes::new(v)
        };
        Vec3Lanes::new(lanes(&self.r), lanes(&self.g), lanes(&self.b))
    }

    /// Writes lanes of `v` to samples `start ..`, stopping at the end (of
    /// the shortest channel, should the public channels differ in length).
    #[inline]
    pub fn store_block(&mut self, start: usize, v: Vec3Lanes) {
        let len = self.r.len().min(self.g.len()).min(self.b.len());
        let n = len.saturating_sub(start).min(LANES);
        if n == 0 {
            return;
        }
        for (dst, src) in [(&mut self.r, v.x), (&mut self.g, v.y), (&mut self.b, v.z)] {
            dst[start..start + n].copy_from_slice(&src.as_array()[..n]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_round_trip_with_padding() {
        let mut s = ShadingSamples::default();
        for i in 0..11 {
            s.push(
                Vec3::new(i as f32, 0.0, 0.0),
                Vec3::Z,
                Vec3::new(0.0, 0.0, -(i as f32)),
            );
        }
        let (t, wi, wo) = s.load_block(8);
        assert_eq!(t.lane(2), Vec3::new(10.0, 0.0, 0.0));
        assert_eq!(t.lane(3), Vec3::X, "padding is a valid direction");
        assert_eq!(wi.lane(0), Vec3::Z);
        assert_eq!(wo.lane(1), Vec3::new(0.0, 0.0, -9.0));
        let mut out = RgbBuffer::zeros(11);
        out.store_block(8, t);
        assert_eq!(out.get(10), Vec3::splat(10.0) * Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(out.len(), 11);
    }
}
