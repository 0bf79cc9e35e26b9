//! Fixed-step accumulator: Verlet as written needs a constant dt (the
//! `x - x_prev` term is a velocity times the *previous* dt), so a variable
//! frame time is turned into whole substeps of the fixed dt (Fiedler, "Fix
//! your timestep"), with a cap so a long hitch cannot spiral.

use crate::Error;

/// Turns frame times into a whole number of fixed substeps.
#[derive(Clone, Debug, PartialEq)]
pub struct FixedStep {
    dt: f32,
    max_substeps: u32,
    accumulated: f32,
}

impl FixedStep {
    /// `dt`: the fixed step (> 0); `max_substeps`: at most this many steps per
    /// frame (>= 1); time beyond it is dropped (the hair slows down rather
    /// than the frame rate collapsing).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidParameter`] if `dt` is not finite and > 0 or
    /// `max_substeps` is 0.
    pub fn new(dt: f32, max_substeps: u32) -> Result<Self, Error> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::InvalidParameter {
                name: "dt",
                value: dt,
                expected: "a finite dt > 0",
            });
        }
        if max_substeps == 0 {
            return Err(Error::InvalidParameter {
                name: "max_substeps",
                value: 0.0,
                expected: ">= 1",
            });
        }
        Ok(FixedStep {
            dt,
            max_substeps,
            accumulated: 0.0,
        })
    }

    /// The fixed step in seconds.
    pub fn dt(&self) -> f32 {
        self.dt
    }

    /// Adds a frame's time and returns how many fixed steps to run now.
    /// Negative or non-finite frame times count as 0.
    pub fn advance(&mut self, frame_time: f32) -> u32 {
        if frame_time.is_finite() && frame_time > 0.0 {
            self.accumulated += frame_time;
        }
        let whole = (self.accumulated / self.dt).floor();
        if whole > self.max_substeps as f32 {
            // A hitch: run the cap and keep only the fraction of a step.
            self.accumulated = self.accumulated.rem_euclid(self.dt);
            return self.max_substeps;
        }
        self.accumulated = (self.accumulated - whole * self.dt).clamp(0.0, self.dt);
        whole as u32
    }

    /// Fraction of a step left over, in [0, 1]: for interpolating the drawn
    /// pose between the last two steps.
    pub fn remainder(&self) -> f32 {
        (self.accumulated / self.dt).clamp(0.0, 1.0)
    }
}
