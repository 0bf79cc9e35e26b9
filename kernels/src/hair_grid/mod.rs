//! Hair against hair: volume and friction through a grid of the hair,
//! rebuilt once per step, between the blocks' steps.
//!
//! Guide strands pass through each other; the hair they stand for has
//! volume and rubs. Following Petrovic, Henne and Anderson 2005 ("Volumetric
//! methods for simulation and rendering of hair", Pixar) and McAdams et al.
//! 2009 ("Detail preserving continuum simulation of straight hair"), the
//! step grids the hair and lets each vertex feel the hair around it:
//!
//! 1. **Splat** (`grid.rs`): every vertex `i` adds its weight `s_i` and
//!    momentum `s_i v_i` (`v_i = (x_i - x_prev_i) / dt`) to the eight
//!    nodes of its cell, trilinearly (cloud in cell). The sums are 32-bit
//!    integers in fixed point, so they are exact and the same bytes in any
//!    order and grouping: the lane groups are cut into parts, one per
//!    thread of the step's executor (at most [`MAX_SPLAT_PARTS`]),
//!    each part sums into its own grid as a task, and the other parts'
//!    nodes are then added into the first's. One thread runs one part, as
//!    one grid. A term is `round(2^w c s_i)` for the weight and
//!    `round(2^m c s_i v_i)` per velocity component (`c` the corner's
//!    trilinear weight, `s_i` at most 1: hair shares are taken over the
//!    largest), with `w = 30 - ceil(log2 N)` for `N` vertex lanes, so that
//!    no sum can pass `2^30` even with every vertex in one cell, and
//!    `m = w - b` with `2^b` the step's largest velocity component
//!    (at most 100 m/s; every component is clamped to `2^b`): each term is
//!    within half a unit of the real one (for Sintel's 7,424 vertex lanes
//!    a unit is `2^-17` of weight). Floating-point sums would depend on
//!    the order of their terms, so per-part float grids could not give
//!    the same bytes at every thread count. The first
//!    vertex in a cell lists the cell (a per-node stamp, never cleared);
//!    after the splat the listed cells' nodes that took weight are the
//!    step's nodes, over which everything below runs, so the cost follows
//!    the hair, not its box. `s_i` ramps from 0 at the root to 1 at
//!    [`ROOT_RAMP`] of arc length: the roots' crowd on the scalp is the
//!    groom's, not hair to push apart.
//! 2. **Fields** per node: the density `rho = sum s / cell^3`, its excess
//!    `e = max(rho / rho_0 - 1, 0)` over the target `rho_0` (the densest
//!    node of the groomed pose, gridded the same way, `HairGrid::target`),
//!    a pressure `p` from [`grid::JACOBI_SWEEPS`] Jacobi sweeps of the
//!    Poisson equation `-lap(p) = e` over the hair's nodes (`p = 0` where
//!    there is none; as Unity's hair system solves its pressure), the
//!    pressure's gradient by central differences (per cell), the hair's
//!    velocity `sum s v / sum s` and `rho / rho_0`. (Pushing down the
//!    excess's own gradient instead, as Petrovic et al. do, was measured and
//!    not taken: less volume and slower to settle.)
//! 3. **Apply** (`apply.rs`, per block, in lanes, as tasks; a scalar twin):
//!    each free vertex reads the two fields trilinearly at its position:
//!    - volume: the push `d = -volume_stiffness 0.75 cell grad(p)` (at most
//!      0.75 cell) raises its velocity along `d` to at least `|d| / dt`;
//!    - friction: its velocity moves toward the hair's by `hair_friction`
//!      (`v += f (v_grid - v)`, through its previous position), so
//!      velocities relative to the neighbours decay and the common motion
//!      stays.
//!
//! Only compression is pushed back (`e >= 0`); sparse hair at rest feels
//! nothing (no excess; its velocity is its own and zero).

mod apply;
pub(crate) mod grid;

pub(crate) use apply::{apply_block, GridSetup};
pub(crate) use grid::HairGrid;
pub use grid::{JACOBI_SWEEPS, MAX_SPLAT_PARTS};

/// Arc length (metres) over which a vertex's weight in the grid and its
/// response ramp from 0 at the root to 1.
pub const ROOT_RAMP: f32 = 0.02;

/// The most nodes a hair grid holds (`2^20`: 32 MiB of node fields); a box
/// that needs more is gridded coarser.
pub const MAX_HAIR_GRID_NODES: usize = 1 << 20;
