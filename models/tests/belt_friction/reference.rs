//! An independent event-driven solution of the stick-slip oscillator, in closed form:
//! a mass `m` on a spring `k` (to a wall, relaxed at x = 0) riding a belt that moves at
//! `v_b > 0`, with Coulomb friction of static limit `fs` and kinetic level `fc`.
//!
//! - Slip (v ≠ v_b): the friction force is `fc` against the slip velocity, so the mass
//!   oscillates harmonically (ω = √(k/m)) about the shifted equilibrium `±fc/k`. The
//!   phase ends when the velocity next reaches `v_b` (from below when the mass is
//!   slower than the belt, from above when faster): the crossing of the circle
//!   (x − c)² + (v/ω)² = R² with the line v = v_b, solved exactly with `asin`.
//! - There the mass sticks if the spring force it must hold, |k x|, is at most `fs`;
//!   otherwise it slips on the other way.
//! - Stick (v = v_b): uniform motion with the belt, friction force `k x`; the phase ends
//!   when `k x` reaches `fs` (breakaway), at a time solved exactly.
//!
//! Nothing here is shared with the model or the runtime: it is the textbook piecewise
//! solution (e.g. Popp & Stelter, "Stick-slip vibrations and chaos", Phil. Trans. R.
//! Soc. A 332 (1990), the belt-driven oscillator), written out for these tests.

use core::f64::consts::TAU;

/// The belt-driven oscillator's data.
#[derive(Clone, Copy, Debug)]
pub struct Belt {
    /// Mass, kg.
    pub m: f64,
    /// Spring stiffness, N/m.
    pub k: f64,
    /// Belt speed, m/s (> 0).
    pub v_b: f64,
    /// Static friction limit, N.
    pub fs: f64,
    /// Kinetic friction force, N (≤ fs).
    pub fc: f64,
}

/// What the contact does during a phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The mass moves with the belt.
    Stick,
    /// The mass is slower than the belt: friction `+fc` drags it forward.
    SlipSlower,
    /// The mass is faster than the belt: friction `-fc` holds it back.
    SlipFaster,
}

/// One phase: from `t0` (state `x0`, `v0`) to `t1`.
#[derive(Clone, Copy, Debug)]
pub struct Segment {
    /// What the contact does.
    pub phase: Phase,
    /// Start, s.
    pub t0: f64,
    /// End, s (the run's end for the last one).
    pub t1: f64,
    /// Position at the start, m.
    pub x0: f64,
    /// Velocity at the start, m/s.
    pub v0: f64,
}

impl Belt {
    fn omega(&self) -> f64 {
        (self.k / self.m).sqrt()
    }

    /// The friction force on the mass in a slip phase.
    fn slip_force(&self, phase: Phase) -> f64 {
        match phase {
            Phase::SlipSlower => self.fc,
            Phase::SlipFaster => -self.fc,
            Phase::Stick => unreachable!("a stick phase's force is k x"),
        }
    }

    /// The phase a state starts in: stuck if it moves with the belt and the spring
    /// force is within the static limit.
    fn phase_at(&self, x: f64, v: f64) -> Phase {
        if v < self.v_b {
            Phase::SlipSlower
        } else if v > self.v_b {
            Phase::SlipFaster
        } else if (self.k * x).abs() <= self.fs {
            Phase::Stick
        } else if self.k * x > 0.0 {
            // The spring pulls back harder than friction holds: the mass falls behind.
            Phase::SlipSlower
        } else {
            Phase::SlipFaster
        }
    }

    /// The state `tau` after the start of a phase that began at (`x0`, `v0`).
    pub fn state(&self, phase: Phase, x0: f64, v0: f64, tau: f64) -> (f64, f64) {
        match phase {
            Phase::Stick => (x0 + self.v_b * tau, self.v_b),
            _ => {
                let w = self.omega();
                let c = self.slip_force(phase) / self.k;
                let (s, co) = (w * tau).sin_cos();
                let x = c + (x0 - c) * co + v0 / w * s;
                let v = -(x0 - c) * w * s + v0 * co;
                (x, v)
            }
        }
    }

    /// How long a phase that starts at (`x0`, `v0`) lasts; `None` if it never ends.
    fn duration(&self, phase: Phase, x0: f64, v0: f64) -> Option<f64> {
        if phase == Phase::Stick {
            // k x rises to fs with the belt's motion.
            return Some((self.fs / self.k - x0) / self.v_b);
        }
        let w = self.omega();
        let c = self.slip_force(phase) / self.k;
        // x − c = R cos ψ, v = −R ω sin ψ, ψ = ω τ − β.
        let (dx, dv) = (x0 - c, v0 / w);
        let r = dx.hypot(dv);
        let ratio = self.v_b / (r * w);
        if ratio > 1.0 {
            return None;
        }
        let beta = dv.atan2(dx);
        let a = ratio.asin();
        // v reaches v_b rising at ψ = π + a, falling at ψ = −a.
        let target = match phase {
            Phase::SlipSlower => core::f64::consts::PI + a,
            _ => -a,
        };
        let mut sweep = (target + beta).rem_euclid(TAU);
        // Starting on the other crossing (a breakaway) the sweep is > 0; starting on this
        // one (rounding) means a whole turn.
        if sweep < 1e-12 {
            sweep += TAU;
        }
        Some(sweep / w)
    }

    /// The phases from (`x0`, `v0`) at t = 0 up to `t_end`.
    pub fn solve(&self, x0: f64, v0: f64, t_end: f64) -> Vec<Segment> {
        let mut segments = Vec::new();
        let (mut t, mut x, mut v) = (0.0, x0, v0);
        let mut phase = self.phase_at(x, v);
        while t < t_end {
            let t1 = self
                .duration(phase, x, v)
                .map_or(t_end, |d| (t + d).min(t_end));
            segments.push(Segment {
                phase,
                t0: t,
                t1,
                x0: x,
                v0: v,
            });
            let (x1, v1) = self.state(phase, x, v, t1 - t);
            // At a phase's end the velocity is exactly the belt's.
            (t, x, v) = (t1, x1, if t1 < t_end { self.v_b } else { v1 });
            phase = match phase {
                Phase::Stick if self.k * x > 0.0 => Phase::SlipSlower,
                Phase::Stick => Phase::SlipFaster,
                _ => self.phase_at(x, self.v_b),
            };
        }
        segments
    }

    /// The state at `t` from the phases.
    pub fn at(&self, segments: &[Segment], t: f64) -> (f64, f64) {
        let s = segments
            .iter()
            .find(|s| t <= s.t1)
            .or(segments.last())
            .expect("at least one phase");
        self.state(s.phase, s.x0, s.v0, t - s.t0)
    }

    /// The energy the contact dissipates in a phase: `fc` times the distance the mass
    /// slides over the belt (the slip velocity keeps its sign within a phase).
    pub fn friction_loss(&self, s: &Segment) -> f64 {
        match s.phase {
            Phase::Stick => 0.0,
            _ => {
                let (x1, _) = self.state(s.phase, s.x0, s.v0, s.t1 - s.t0);
                self.fc * ((x1 - s.x0) - self.v_b * (s.t1 - s.t0)).abs()
            }
        }
    }

    /// The work the belt does on the mass through the contact in a phase: the
    /// friction force times the belt's displacement.
    pub fn belt_work(&self, s: &Segment) -> f64 {
        let dt = s.t1 - s.t0;
        match s.phase {
            // ∫ k x v_b dt with x = x0 + v_b τ.
            Phase::Stick => self.k * self.v_b * (s.x0 * dt + 0.5 * self.v_b * dt * dt),
            _ => self.slip_force(s.phase) * self.v_b * dt,
        }
    }

    /// Kinetic plus elastic energy.
    pub fn energy(&self, x: f64, v: f64) -> f64 {
        0.5 * self.m * v * v + 0.5 * self.k * x * x
    }
}
