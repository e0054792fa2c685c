//! The work counters of a run, shared by every method and driver.

/// The work done by one run (by one of the integrators of [`crate::rk`]: since it was
/// made).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct Stats {
    /// Steps accepted.
    pub accepted: usize,
    /// Steps rejected: error estimate too large, a non-finite value met, or (stiff
    /// methods) a Newton iteration that failed or a singular iteration matrix.
    pub rejected: usize,
    /// Evaluations of [`Model::derivatives`](crate::Model::derivatives) on `f64`, by the
    /// method itself (the evaluations for Jacobians are counted in
    /// [`Stats::n_jac_rhs`]).
    pub n_rhs: usize,
    /// Jacobians evaluated (stiff methods; 0 for the explicit ones).
    pub n_jac: usize,
    /// LU factorizations of iteration matrices (stiff methods). Radau5 factors two
    /// matrices each time, one real and one complex (about four times the work of the
    /// real one): both are counted. Rodas4 factors one per attempted step.
    pub n_lu: usize,
    /// Of [`Stats::n_lu`], the factorizations by the sparse code (with pivots fixed at
    /// set-up) that failed its stability test and were done again with partial
    /// pivoting (stiff methods on models whose Jacobian is sparse enough; see
    /// [`JacobianEvaluator`](crate::JacobianEvaluator)).
    pub n_lu_fallback: usize,
    /// Directional derivatives of [`Model::derivatives`](crate::Model::derivatives) spent
    /// on Jacobians (stiff methods): one per colour of the sparsity pattern, or of the
    /// numerical pattern plus one for the check once that is known (see
    /// [`JacobianEvaluator`](crate::JacobianEvaluator); none for a hand-written
    /// [`Model::jacobian`](crate::Model::jacobian)), evaluated
    /// [`LANES`](crate::jacobian::LANES) at a time on dual numbers; plus, for Rodas4, one
    /// `f64` evaluation for `∂f/∂t`.
    pub n_jac_rhs: usize,
    /// Events handled: each firing of an event counts once, simultaneous ones each
    /// (see [`crate::event`]).
    pub events: usize,
    /// Evaluations of [`Model::event_indicators`](crate::Model::event_indicators):
    /// one after every accepted step, plus those spent locating events and restarting
    /// after them (0 for a model without events).
    pub n_event_fn: usize,
    /// Accepted Dormand–Prince steps that Hairer's stiffness test found stiff
    /// (`h |λ| > 3.25`; see
    /// [`DormandPrinceOptions::detect_stiffness`](crate::DormandPrinceOptions::detect_stiffness)).
    pub n_stiff_steps: usize,
}

impl Stats {
    /// Steps attempted: accepted plus rejected. This is what `max_steps` limits.
    pub fn steps(&self) -> usize {
        self.accepted + self.rejected
    }

    /// Adds the work counted in `other` to these counters.
    pub(crate) fn add(&mut self, other: Stats) {
        self.accepted += other.accepted;
        self.rejected += other.rejected;
        self.n_rhs += other.n_rhs;
        self.n_jac += other.n_jac;
        self.n_lu += other.n_lu;
        self.n_lu_fallback += other.n_lu_fallback;
        self.n_jac_rhs += other.n_jac_rhs;
        self.events += other.events;
        self.n_event_fn += other.n_event_fn;
        self.n_stiff_steps += other.n_stiff_steps;
    }
}
