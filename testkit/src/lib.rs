//! coif-testkit: fixtures the crates' own tests share (a dev-dependency
//! only, never part of the library).
//!
//! - [`counting`]: a counting global allocator for the "allocates nothing
//!   per frame" tests.
//! - [`groom_path`]: where the shared TressFX grooms are, or a skip message.
#![warn(missing_docs)]

pub mod counting;

use std::path::PathBuf;

/// The path of a shared groom (`shared/data/grooms/NAME` beside the
/// repository), or None with a message when the folder is absent, so that
/// tests needing it skip rather than fail.
pub fn groom_path(name: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data/grooms")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: {} is absent (the shared groom folder is not beside the repository)",
            p.display()
        );
        None
    }
}
