//! A bouncing ball with events, integrated without the standard library.

use bgdsl_runtime::rk::DormandPrince;
use bgdsl_runtime::{bond_graph, DormandPrinceOptions, Model, SolverError};

bond_graph! {
    /// A ball dropped onto a rigid floor: between impacts it falls freely; at an
    /// impact its momentum turns over and shrinks by the coefficient of restitution;
    /// once it would rebound slower than `rest_speed` it lies on the floor for good
    /// (the rest mode ends the ever faster bouncing a perfectly rigid floor would
    /// otherwise give, which no integrator can follow).
    ///
    /// States: `body.p`, the momentum (kg·m/s, upwards), `height` (m), and the mode
    /// `resting`.
    pub model BouncingBall {
        /// mass of the ball
        param mass = 0.05 in "kg";
        /// gravitational acceleration
        param gravity = 9.81 in "m/s²";
        /// rebound speed over impact speed
        param restitution = 0.9;
        /// the rebound speed below which the ball comes to rest
        param rest_speed = 0.05 in "m/s";
        /// the height it is dropped from, at rest
        param drop_height = 1.0 in "m";

        /// its weight, which the floor carries once the ball rests
        Se weight = if resting { 0.0 } else { -mass * gravity };
        I body = mass;
        weight -> body;

        /// the height of the ball's lowest point above the floor
        state height: f64 = drop_height in "m";
        der height = body.f;

        /// Lying on the floor.
        mode resting: bool = false;

        /// The ball reaches the floor.
        when impact: height < 0.0 {
            if restitution * -body.f < rest_speed {
                resting = true;
                reinit body.p = 0.0;
                reinit height = 0.0;
            } else {
                reinit body.p = -restitution * body.p;
            }
        }

        /// Vertical speed, m/s (upwards).
        output speed = body.f in "m/s";
    }
}

/// The integrator [`BallDrop`] uses: Dormand–Prince for the ball's two states and its
/// mode, with its one event, listing up to two events per call.
pub type BallIntegrator =
    DormandPrince<{ BouncingBall::N_STATES }, { BouncingBall::EVENTS.len() }, 2>;

/// A [`BouncingBall`] with its time, state and adaptive integrator, all inline: what a
/// program without a heap holds to follow the ball tick by tick.
#[derive(Clone, Debug)]
pub struct BallDrop {
    ball: BouncingBall,
    integrator: BallIntegrator,
    t: f64,
    x: [f64; BouncingBall::N_STATES],
}

impl BallDrop {
    /// The ball with `params`, dropped at `t = 0`, integrated to the tolerances of
    /// `options`. Fails if an option is out of range.
    pub fn new(
        params: BouncingBallParams,
        options: DormandPrinceOptions,
    ) -> Result<Self, SolverError> {
        let ball = BouncingBall::new(params);
        let mut x = [0.0; BouncingBall::N_STATES];
        ball.initial_state(&mut x);
        Ok(BallDrop {
            ball,
            integrator: DormandPrince::new(options)?,
            t: 0.0,
            x,
        })
    }

    /// The time reached, s.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The state at [`BallDrop::time`], by name.
    pub fn state(&self) -> BouncingBallState<f64> {
        BouncingBallState::from_slice(&self.x)
    }

    /// Gives the ball's states their own absolute tolerances for later ticks
    /// ([`DormandPrince::set_atol`], in the order of
    /// [`BouncingBall::STATE_NAMES`]); `None` goes back to the options' `atol`.
    ///
    /// # Errors
    ///
    /// [`SolverError::InvalidAtol`] naming the first state whose entry is negative or
    /// not finite (or 0 with `rtol = 0`); the tolerances are then unchanged.
    pub fn set_atol(
        &mut self,
        atol: Option<[f64; BouncingBall::N_STATES]>,
    ) -> Result<(), SolverError> {
        self.integrator.set_atol::<BouncingBall>(atol)
    }

    /// Follows the ball for `dt` seconds, handling its impacts on the way; their times
    /// (at most two per tick are listed, more are counted) are in
    /// [`BallDrop::impacts`]. Fails if `dt` is negative or not finite, or if the
    /// integrator fails; the drop then holds the last point it reached.
    pub fn tick(&mut self, dt: f64) -> Result<(), SolverError> {
        let t_end = self.t + dt;
        self.integrator
            .advance_to(&self.ball, &mut self.t, &mut self.x, t_end)
    }

    /// The impacts of the last tick: their times, and how many more there were.
    pub fn impacts(&self) -> (&[f64], usize) {
        let events = self.integrator.events();
        (events.times(), events.dropped())
    }
}
