//! The quick return mechanism of the flagship with switching in it: Coulomb friction
//! with stiction in its two slides ([`QuickReturnFriction`]), and an end stop on the
//! output slider's guide ([`QuickReturnEndStop`]). Both write the spec's results file
//! and the paper's figures like the flagship, plus their own columns.

pub mod end_stop;
pub mod friction;

pub use end_stop::{QuickReturnEndStop, QuickReturnEndStopParams};
pub use friction::{QuickReturnFriction, QuickReturnFrictionParams};

use crate::quick_return::QuickReturnParams;
use crate::quick_return_rigid::{rigid_params_of, Mechanism, RigidParams};

/// The flagship's parameters out of a variant's, which has all of them (and more).
macro_rules! flagship_params {
    ($p:expr) => {{
        let p = $p;
        QuickReturnParams {
            m1: p.m1,
            m2: p.m2,
            m3: p.m3,
            m4: p.m4,
            m5: p.m5,
            l1: p.l1,
            l2: p.l2,
            l3: p.l3,
            l4: p.l4,
            l5: p.l5,
            d: p.d,
            g: p.g,
            w_drive: p.w_drive,
            theta0: p.theta0,
            K01: p.K01,
            R01: p.R01,
            K12: p.K12,
            R12: p.R12,
            K03: p.K03,
            R03: p.R03,
            K3C: p.K3C,
            R3C: p.R3C,
            K23r: p.K23r,
            R23r: p.R23r,
            K_C: p.K_C,
            R_C: p.R_C,
            K34: p.K34,
            R34: p.R34,
            K45: p.K45,
            R45: p.R45,
            K5C: p.K5C,
            R5C: p.R5C,
            k3c_point_under_slider: p.k3c_point_under_slider,
        }
    }};
}

impl QuickReturnFrictionParams {
    /// The flagship's parameters: these without the friction's.
    pub fn flagship(&self) -> QuickReturnParams {
        flagship_params!(self)
    }
}

impl Mechanism for QuickReturnFrictionParams {
    fn rigid_params(&self) -> RigidParams {
        rigid_params_of!(self)
    }

    fn drive_speed(&self) -> f64 {
        self.w_drive
    }
}

impl QuickReturnEndStopParams {
    /// The flagship's parameters: these without the stop's.
    pub fn flagship(&self) -> QuickReturnParams {
        flagship_params!(self)
    }
}

impl Mechanism for QuickReturnEndStopParams {
    fn rigid_params(&self) -> RigidParams {
        rigid_params_of!(self)
    }

    fn drive_speed(&self) -> f64 {
        self.w_drive
    }
}
