//! The quick return mechanism with rigid joints.
//!
//! - [`reference`]: the rigid-body reference, closed-form kinematics and inverse
//!   dynamics (Newton–Euler for every link), independent of any bond graph. Its items
//!   are re-exported here, where the tests and benches have always found them.
//! - [`model`]: the mechanism as a bond graph with rigid joints
//!   ([`QuickReturnRigid`], driven by a flow source; [`QuickReturnRigidCoupled`],
//!   driven through the paper's compliant drive coupling).
//! - [`mechanism`]: what the figures and summaries read of any quick return model's
//!   parameters ([`Mechanism`]).
//! - [`pose`]: the closed-form pose the bond graph's moduli read.

pub mod mechanism;
pub mod model;
pub mod pose;
pub mod reference;

pub use mechanism::{DrivenMechanism, Mechanism};
pub use model::{
    QuickReturnRigid, QuickReturnRigidCoupled, QuickReturnRigidCoupledParams,
    QuickReturnRigidParams,
};
pub(crate) use reference::rigid_params_of;
pub use reference::*;
