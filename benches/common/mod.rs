//! What the benches share: the executors of the `threads` groups.

use coif::kernels::tasks::{Executor, Serial};

/// A named executor.
pub type Named = (String, Box<dyn Executor>);

/// `Serial`, then coif's own workers of 2 threads (the caller and one
/// worker), then rayon pools of 1 and 2 threads (feature `rayon`).
pub fn executors() -> Vec<Named> {
    let serial: Named = ("serial".into(), Box::new(Serial));
    let workers: Named = (
        "workers2".into(),
        Box::new(coif::kernels::tasks::Workers::new(2).unwrap()),
    );
    [serial, workers].into_iter().chain(pools()).collect()
}

#[cfg(feature = "rayon")]
fn pools() -> impl Iterator<Item = Named> {
    [1, 2].into_iter().map(|n| {
        let pool = coif::kernels::tasks::Rayon::new(n).unwrap();
        (format!("rayon{n}"), Box::new(pool) as Box<dyn Executor>)
    })
}

#[cfg(not(feature = "rayon"))]
fn pools() -> impl Iterator<Item = Named> {
    std::iter::empty()
}
