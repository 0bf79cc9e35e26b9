//! PLACEHOLDER until the sdf branch lands (replaced by the real field).
#![allow(dead_code, missing_docs)]
use crate::lanes::{Lane, V3};
use crate::Error;
use glam::{Affine3A, Vec3};
use wide::f32x8;

pub const MAX_SDF_CELLS: u64 = 1 << 24;

#[derive(Clone, Debug)]
pub struct Sdf {
    world_from_mesh: Affine3A,
    lo: Vec3,
    hi: Vec3,
}

impl Sdf {
    pub fn from_mesh(_p: &[Vec3], _t: &[[u32; 3]], _cell: f32) -> Result<Sdf, Error> {
        Err(Error::NoStrands)
    }
    pub fn distance(&self, _p: Vec3) -> f32 {
        f32::INFINITY
    }
    pub fn set_transform(&mut self, x: Affine3A) -> Result<(), Error> {
        self.world_from_mesh = x;
        Ok(())
    }
    pub fn transform(&self) -> Affine3A {
        self.world_from_mesh
    }
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.lo, self.hi)
    }
}

pub(crate) trait SdfLane: Lane {
    fn sample(sdf: &Sdf, p_mesh: V3<Self>) -> (Self, V3<Self>);
}
impl SdfLane for f32 {
    fn sample(_sdf: &Sdf, _p: V3<f32>) -> (f32, V3<f32>) {
        (f32::INFINITY, V3::zero())
    }
}
impl SdfLane for f32x8 {
    fn sample(_sdf: &Sdf, _p: V3<f32x8>) -> (f32x8, V3<f32x8>) {
        (f32x8::splat(f32::INFINITY), V3::zero())
    }
}
