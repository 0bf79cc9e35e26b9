//! Dev-only fixtures of the coif-lod tests.
#![allow(dead_code)]

pub mod counting;
