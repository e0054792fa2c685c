//! What the results' figures and summaries need of a quick return model's parameters:
//! the rigid mechanism they describe and the speed its crank is driven at, whichever
//! model (compliant or rigid joints) they belong to.

use super::model::{QuickReturnRigidCoupledParams, QuickReturnRigidParams};
use super::reference::{rigid_params_of, RigidParams};
use crate::quick_return::QuickReturnParams;

/// A quick return model's parameters seen as a driven rigid mechanism.
pub trait Mechanism {
    /// The rigid mechanism with the model's links, pivot distance, gravity and slide
    /// frictions.
    fn rigid_params(&self) -> RigidParams;
    /// The speed the crank is driven at, rad/s.
    fn drive_speed(&self) -> f64;
}

/// A rigid mechanism driven at a speed: a [`Mechanism`] by value.
#[derive(Clone, Debug, PartialEq)]
pub struct DrivenMechanism {
    /// The mechanism.
    pub rigid: RigidParams,
    /// The crank's drive speed, rad/s.
    pub drive_speed: f64,
}

impl DrivenMechanism {
    /// The mechanism `params` describe.
    pub fn of(params: &dyn Mechanism) -> Self {
        DrivenMechanism {
            rigid: params.rigid_params(),
            drive_speed: params.drive_speed(),
        }
    }
}

impl Mechanism for DrivenMechanism {
    fn rigid_params(&self) -> RigidParams {
        self.rigid.clone()
    }

    fn drive_speed(&self) -> f64 {
        self.drive_speed
    }
}

impl Mechanism for QuickReturnParams {
    fn rigid_params(&self) -> RigidParams {
        rigid_params_of!(self)
    }

    fn drive_speed(&self) -> f64 {
        self.w_drive
    }
}

/// The rigid models' parameters carry the slide frictions as numbers (the friction
/// along the slide is all a rigid prismatic joint has).
macro_rules! rigid_model_mechanism {
    ($($params:ty),*) => {$(
        impl Mechanism for $params {
            fn rigid_params(&self) -> RigidParams {
                RigidParams {
                    m1: self.m1,
                    m2: self.m2,
                    m3: self.m3,
                    m4: self.m4,
                    m5: self.m5,
                    l1: self.l1,
                    l2: self.l2,
                    l3: self.l3,
                    l4: self.l4,
                    l5: self.l5,
                    d: self.d,
                    g: self.g,
                    R3C: self.R3C,
                    R5C: self.R5C,
                }
            }

            fn drive_speed(&self) -> f64 {
                self.w_drive
            }
        }
    )*};
}

rigid_model_mechanism!(QuickReturnRigidParams, QuickReturnRigidCoupledParams);
