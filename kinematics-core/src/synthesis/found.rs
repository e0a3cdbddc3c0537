//! What a search reports and finds: its progress, what stopped it, and
//! the distinct optima, ranked.

use std::vec::Vec;

#[cfg(doc)]
use super::Search;
use super::design::Synthesized;
use super::subject::Subject;

/// Where a search is, as reported to [`Search::progress`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Starts screened so far (a short refinement each).
    pub screened: usize,
    /// Of how many.
    pub starts: usize,
    /// Designs refined to convergence so far.
    pub refined: usize,
    /// Of at most how many.
    pub keep: usize,
    /// The lowest E so far (∞ before the first).
    pub best: f64,
    /// Residual and Jacobian evaluations so far.
    pub evaluations: usize,
}

/// What stopped a search before it had refined the designs it keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Budget {
    /// The evaluations given to [`Search::evaluations`] were spent.
    Evaluations,
    /// The time given to [`Search::time`] ran out.
    Time,
}

/// One local optimum a search found.
#[derive(Debug, Clone)]
pub struct Optimum<M: Subject> {
    /// The refinement that ended there (the design, its driver values at
    /// the targets, E, each target's error, whether it turns fully).
    pub found: Synthesized<M>,
    /// Whether every constraint holds: the linear inequalities and the
    /// order (at the design), and over the motion one branch from target
    /// to target, the transmission angles, the regions and, where asked,
    /// a full turn.
    pub feasible: bool,
    /// Over the motion (a turn if the design turns fully, else from the
    /// smallest driver value of the targets to the largest), the smallest
    /// transmission angle of the dyads named to [`Search::transmission`],
    /// folded into [0, π/2] (min(μ, π − μ), rad); `None` with no dyad
    /// named.
    pub min_transmission: Option<f64>,
    /// Whether the motion passes from target to target without stopping
    /// (no dead centre, no change of assembly between them: the targets
    /// are on one branch and one circuit).
    pub one_branch: bool,
    /// How many of the refined starts ended at this optimum.
    pub reached_by: usize,
    /// The design's pose at each target, in its assembly modes (empty if
    /// one does not assemble).
    pub poses: Vec<M::Pose>,
}

/// What a search found.
#[derive(Debug, Clone)]
pub struct Found<M: Subject> {
    /// The distinct optima, the feasible first, each group by E
    /// ascending.
    pub optima: Vec<Optimum<M>>,
    /// Residual and Jacobian evaluations of the refinements, every start
    /// (the designs drawn and rejected, and the sweeps that check the
    /// results over their motion, are not counted).
    pub evaluations: usize,
    /// The starts screened (each feasible at its starting driver values).
    pub starts: usize,
    /// The starts that gave no screened design: none was drawn feasible
    /// in the tries allowed, or its screening failed.
    pub undrawn: usize,
    /// What stopped the search early, if anything did.
    pub stopped_by: Option<Budget>,
}

impl<M: Subject> Found<M> {
    /// The best feasible optimum.
    #[must_use]
    pub fn best(&self) -> Option<&Optimum<M>> {
        self.optima.first().filter(|o| o.feasible)
    }
}
