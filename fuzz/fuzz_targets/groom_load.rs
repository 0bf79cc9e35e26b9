//! `cargo fuzz run groom_load`: any bytes through `coif::groom::load` must
//! give a groom or an error, never a panic, a hang or an allocation far
//! beyond the input's size; a groom that loads must be consistent, and
//! survive a cyHair round trip.
#![no_main]

use coif::groom::{self, cyhair};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(g) = groom::load(data) {
        assert!(g.strand_count() > 0);
        assert!(g.vertex_count() * 12 <= data.len());
        assert!(g.points().iter().all(|p| p.is_finite()));
        if let Ok(bytes) = cyhair::write(&g, "fuzz") {
            assert_eq!(groom::load(&bytes).as_ref(), Ok(&g));
        }
    }
});
