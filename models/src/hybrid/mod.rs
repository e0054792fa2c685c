//! Textbook hybrid models: continuous dynamics with events and discrete modes, built
//! on the standard library's switching elements, each checked in
//! `models/tests/hybrid_*.rs` against a closed form.
//!
//! - [`BouncingBall`]: a ball dropped on a floor (impact with restitution, rest mode).
//! - [`HalfWaveRectifier`]: a sine source, an ideal diode and an RC load.
//! - [`HalfWaveRectifierExp`]: the same with an exponential-law diode (smooth).
//! - [`EndStop`]: a mass on a spring hitting an end stop with restitution.
//! - [`BeltFriction`]: a mass on a spring riding a belt, with stick-slip friction;
//!   [`BeltFrictionSmooth`] the same on a steep smooth friction law.
//! - [`ClutchEngagement`]: two shafts joined by a clutch that locks at a speed match.
//! - [`BallPenalty`]: the ball on a steep smooth penalty contact (no events), for the
//!   benchmark against [`BouncingBall`].

mod ball;
mod belt_friction;
mod clutch;
mod end_stop;
mod rectifier;

pub use ball::{BallPenalty, BallPenaltyParams, BouncingBall, BouncingBallParams};
pub use belt_friction::{
    BeltFriction, BeltFrictionParams, BeltFrictionSmooth, BeltFrictionSmoothParams,
};
pub use clutch::{ClutchEngagement, ClutchEngagementParams};
pub use end_stop::{EndStop, EndStopParams};
pub use rectifier::{
    HalfWaveRectifier, HalfWaveRectifierExp, HalfWaveRectifierExpParams,
    HalfWaveRectifierParams,
};
