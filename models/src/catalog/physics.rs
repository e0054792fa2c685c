//! What the catalogue needs of a model beyond [`Model`]: how to make one from its
//! parameters, and which parameter values make physical sense for it.

use bgdsl_runtime::multibond::box_inertia;

use super::Checks;
use crate::dc_servo::DcServo;
use crate::hybrid::{
    BeltFriction, BouncingBall, ClutchEngagement, EndStop, HalfWaveRectifier, HalfWaveRectifierExp,
};
use crate::quick_return::{assembly, QuickReturn, QuickReturnParams};
use crate::quick_return_hybrid::{QuickReturnEndStop, QuickReturnFriction};
use crate::quick_return_rigid::{
    try_quick_return_cycle, DrivenMechanism, Mechanism, QuickReturnRigid, QuickReturnRigidCoupled,
};
use crate::{Butterworth, DcMotor, Duffing, Oscillator, QuarterCar, SeriesRlc};

/// A model of the catalogue, with physical checks of the parameters (beyond "every
/// number is finite", which the catalogue checks for all): [`Entry::of`]'s `checks`,
/// and the FMI library's.
///
/// [`Entry::of`]: bgdsl_cli::Entry::of
pub trait Catalogued:
    bgdsl_runtime::WithInputs + bgdsl_runtime::FromParams + Default + Sync + Sized + 'static
{
    /// Records in `checks` every physically meaningless value of `params`: a mass of
    /// zero, a negative stiffness, a link that cannot be assembled.
    fn check_params(params: &Self::Params, checks: &mut Checks);
    /// The rigid mechanism a quick return model's parameters describe (for its
    /// results' figures and summary); `None` for the other models.
    fn mechanism(params: &Self::Params) -> Option<DrivenMechanism> {
        let _ = params;
        None
    }
}

impl Catalogued for QuickReturn {
    fn mechanism(params: &QuickReturnParams) -> Option<DrivenMechanism> {
        Some(DrivenMechanism::of(params))
    }

    /// Masses positive; edge lengths not negative, and the length (the x edge) of the
    /// crank, rocker and rod positive, as their points sit at its ends; each link's box
    /// inertia positive definite (at most one edge length 0); `d` positive; stiffnesses
    /// and dampings not negative; the K3C point switch 0 or 1; and the mechanism can be
    /// assembled at `theta0` (the rod reaches the output slider's guide from the
    /// rocker's tip).
    fn check_params(p: &QuickReturnParams, checks: &mut Checks) {
        let links = [
            ("crank", "m1", p.m1, "l1", p.l1),
            ("slider", "m2", p.m2, "l2", p.l2),
            ("rocker", "m3", p.m3, "l3", p.l3),
            ("connecting rod", "m4", p.m4, "l4", p.l4),
            ("output slider", "m5", p.m5, "l5", p.l5),
        ];
        let mut geometry_ok = true;
        for (link, m_name, m, l_name, l) in links {
            checks.positive(m_name, m);
            let before = checks.count();
            checks.non_negative_each(l_name, &l);
            if matches!(l_name, "l1" | "l3" | "l4") && (l[0].is_nan() || l[0] <= 0.0) {
                let message = format!(
                    "the {link}'s length {l_name}[0] must be > 0 m (its points sit at its \
                     ends), found {}",
                    l[0]
                );
                checks.problem(&[l_name], message);
            }
            if checks.count() > before {
                geometry_ok = false;
                continue;
            }
            if m > 0.0 {
                let j = box_inertia(m, l[0], l[1], l[2]);
                if !(j.x > 0.0 && j.y > 0.0 && j.z > 0.0) {
                    let message = format!(
                        "the {link}'s inertia is not positive definite: the box {l_name} = \
                         [{}, {}, {}] m of mass {m_name} = {m} kg has principal moments \
                         [{:.3e}, {:.3e}, {:.3e}] kg·m²; at most one edge length may be 0",
                        l[0], l[1], l[2], j.x, j.y, j.z
                    );
                    checks.problem(&[l_name, m_name], message);
                }
            }
        }
        checks.positive("d", p.d);
        geometry_ok &= p.d > 0.0;
        for (name, value) in [
            ("K01", p.K01),
            ("R01", p.R01),
            ("K12", p.K12),
            ("R12", p.R12),
            ("K03", p.K03),
            ("R03", p.R03),
            ("K23r", p.K23r),
            ("R23r", p.R23r),
            ("K_C", p.K_C),
            ("R_C", p.R_C),
            ("K34", p.K34),
            ("R34", p.R34),
            ("K45", p.K45),
            ("R45", p.R45),
        ] {
            checks.non_negative(name, value);
        }
        for (name, value) in [
            ("K3C", p.K3C),
            ("R3C", p.R3C),
            ("K5C", p.K5C),
            ("R5C", p.R5C),
        ] {
            checks.non_negative_each(name, &value);
        }
        checks.one_of(
            "k3c_point_under_slider",
            p.k3c_point_under_slider,
            &[0.0, 1.0],
        );
        if geometry_ok {
            let pose = assembly(p.theta0, p.d, p.l1[0], p.l3[0], p.l4[0]);
            let finite = pose
                .position
                .iter()
                .all(|r| r.iter().all(|v| v.is_finite()))
                && pose
                    .orientation
                    .iter()
                    .all(|r| r.iter().all(|v| v.is_finite()));
            if !finite {
                let pin = (p.l1[0] * p.theta0.cos(), p.l1[0] * p.theta0.sin());
                let angle = (pin.1 + p.d).atan2(pin.0);
                let tip_y = -p.d + p.l3[0] * angle.sin();
                let message = format!(
                    "the mechanism cannot be assembled at theta0 = {}: the connecting rod \
                     (l4[0] = {} m) does not reach the output slider's guide (y = 0) from the \
                     rocker's tip at y = {tip_y:.4} m; lengthen l4[0] or change l3[0], d or \
                     theta0",
                    p.theta0, p.l4[0]
                );
                checks.problem(&["l4", "l3", "d", "theta0", "l1"], message);
            }
        }
    }
}

/// The links of a rigid quick return: masses positive; edge lengths not negative, the
/// crank, rocker and rod lengths positive, at most one edge 0; `d` positive; and the
/// mechanism has its quick-return cycle (a crank shorter than `d`, a rod that reaches
/// the guide at every crank angle: else a closure transformer is singular somewhere
/// in the turn).
fn rigid_link_checks(p: &dyn Mechanism, checks: &mut Checks) {
    let rigid = p.rigid_params();
    let links = [
        ("crank", "m1", rigid.m1, "l1", rigid.l1),
        ("slider", "m2", rigid.m2, "l2", rigid.l2),
        ("rocker", "m3", rigid.m3, "l3", rigid.l3),
        ("connecting rod", "m4", rigid.m4, "l4", rigid.l4),
        ("output slider", "m5", rigid.m5, "l5", rigid.l5),
    ];
    let before = checks.count();
    for (link, m_name, m, l_name, l) in links {
        checks.positive(m_name, m);
        checks.non_negative_each(l_name, &l);
        let edges_zero = l.iter().filter(|&&e| e == 0.0).count();
        if edges_zero > 1 {
            let message = format!(
                "the {link}'s inertia about Z0 needs a box: at most one edge of {l_name} may be \
                 0 m, found [{}, {}, {}]",
                l[0], l[1], l[2]
            );
            checks.problem(&[l_name], message);
        }
    }
    checks.positive("d", rigid.d);
    checks.non_negative("R3C", rigid.R3C);
    checks.non_negative("R5C", rigid.R5C);
    if checks.count() == before {
        if let Err(why) = try_quick_return_cycle(&rigid) {
            checks.problem(
                &["l1", "l3", "l4", "d"],
                format!("the rigid mechanism cannot turn: {why}"),
            );
        }
    }
}

impl Catalogued for QuickReturnRigid {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        rigid_link_checks(p, checks);
    }

    fn mechanism(params: &Self::Params) -> Option<DrivenMechanism> {
        Some(DrivenMechanism::of(params))
    }
}

impl Catalogued for QuickReturnRigidCoupled {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        rigid_link_checks(p, checks);
        checks.non_negative("K_C", p.K_C);
        checks.non_negative("R_C", p.R_C);
    }

    fn mechanism(params: &Self::Params) -> Option<DrivenMechanism> {
        Some(DrivenMechanism::of(params))
    }
}

impl Catalogued for Oscillator {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("m", p.m);
        checks.non_negative("k", p.k);
        checks.non_negative("c", p.c);
    }
}

impl Catalogued for Butterworth {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.non_negative("source_resistance", p.source_resistance);
        checks.positive("l1", p.l1);
        checks.positive("c2", p.c2);
        checks.positive("l3", p.l3);
        checks.non_negative("load_resistance", p.load_resistance);
    }
}

impl Catalogued for SeriesRlc {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.non_negative("resistance", p.resistance);
        checks.positive("inductance", p.inductance);
        checks.positive("capacitance", p.capacitance);
    }
}

/// The DC motor and the DC servo (the same motor with its voltage and load torque as
/// inputs) share their drive train, and so its checks.
macro_rules! drive_train_checks {
    ($($model:ident),*) => {$(
        impl Catalogued for $model {
            fn check_params(p: &Self::Params, checks: &mut Checks) {
                checks.non_negative("resistance", p.resistance);
                checks.positive("inductance", p.inductance);
                checks.positive("rotor_inertia", p.rotor_inertia);
                checks.non_negative("rotor_friction", p.rotor_friction);
                checks.positive("gear_ratio", p.gear_ratio);
                checks.non_negative("shaft_stiffness", p.shaft_stiffness);
                checks.non_negative("shaft_damping", p.shaft_damping);
                checks.positive("load_inertia", p.load_inertia);
                checks.non_negative("load_friction", p.load_friction);
            }
        }
    )*};
}

drive_train_checks!(DcMotor, DcServo);

impl Catalogued for QuarterCar {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("sprung_mass", p.sprung_mass);
        checks.positive("unsprung_mass", p.unsprung_mass);
        // The initial state divides by both stiffnesses (the static deflections).
        checks.positive("suspension_stiffness", p.suspension_stiffness);
        checks.non_negative("suspension_damping", p.suspension_damping);
        checks.positive("tyre_stiffness", p.tyre_stiffness);
        checks.positive("speed", p.speed);
        checks.positive("bump_length", p.bump_length);
        checks.positive("wavelength", p.wavelength);
    }
}

impl Catalogued for Duffing {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("m", p.m);
        checks.non_negative("c", p.c);
    }
}

impl Catalogued for BouncingBall {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("m", p.m);
        checks.positive("g", p.g);
        checks.non_negative("h0", p.h0);
        unit_interval(checks, "restitution", p.restitution);
        checks.non_negative("v_rest", p.v_rest);
    }
}

impl Catalogued for HalfWaveRectifier {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.non_negative("amplitude", p.amplitude);
        checks.positive("frequency", p.frequency);
        checks.positive("r_on", p.r_on);
        checks.non_negative("g_off", p.g_off);
        checks.positive("r_load", p.r_load);
        checks.positive("capacitance", p.capacitance);
    }
}

impl Catalogued for HalfWaveRectifierExp {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.non_negative("amplitude", p.amplitude);
        checks.positive("frequency", p.frequency);
        checks.positive("r_source", p.r_source);
        checks.positive("i_s", p.i_s);
        checks.positive("n_vt", p.n_vt);
        checks.positive("r_load", p.r_load);
        checks.positive("capacitance", p.capacitance);
    }
}

impl Catalogued for EndStop {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("m", p.m);
        checks.positive("k", p.k);
        checks.non_negative("amplitude", p.amplitude);
        unit_interval(checks, "restitution", p.restitution);
    }
}

impl Catalogued for ClutchEngagement {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("j1", p.j1);
        checks.positive("j2", p.j2);
        checks.non_negative("tk", p.tk);
        static_limit(checks, ("ts", p.ts), ("tk", p.tk));
    }
}

impl Catalogued for BeltFriction {
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        checks.positive("m", p.m);
        checks.positive("k", p.k);
        checks.positive("v_belt", p.v_belt);
        checks.non_negative("g", p.g);
        checks.non_negative("mu_k", p.mu_k);
        static_limit(checks, ("mu_s", p.mu_s), ("mu_k", p.mu_k));
    }
}

impl Catalogued for QuickReturnFriction {
    fn mechanism(params: &Self::Params) -> Option<DrivenMechanism> {
        Some(DrivenMechanism::of(params))
    }

    /// The flagship's checks, and the friction's: coefficients not negative, the
    /// static one 0 (no stiction) or at least the kinetic one, a stuck slide's
    /// stiffness positive.
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        QuickReturn::check_params(&p.flagship(), checks);
        checks.non_negative("mu", p.mu);
        // mu_s = 0 is kinetic friction alone (no stick mode).
        if p.mu_s != 0.0 {
            static_limit(checks, ("mu_s", p.mu_s), ("mu", p.mu));
        }
        checks.positive("K_stick", p.K_stick);
    }
}

impl Catalogued for QuickReturnEndStop {
    fn mechanism(params: &Self::Params) -> Option<DrivenMechanism> {
        Some(DrivenMechanism::of(params))
    }

    /// The flagship's checks, and the stop's: restitution in [0, 1], a rest speed not
    /// negative (`x_stop` anywhere: beyond the stroke the stop is never reached).
    fn check_params(p: &Self::Params, checks: &mut Checks) {
        QuickReturn::check_params(&p.flagship(), checks);
        unit_interval(checks, "restitution", p.restitution);
        checks.non_negative("v_rest", p.v_rest);
    }
}

/// A coefficient of restitution: in [0, 1].
fn unit_interval(checks: &mut Checks, name: &str, value: f64) {
    if !(0.0..=1.0).contains(&value) {
        checks.problem(&[name], format!("{name} must be in [0, 1], found {value}"));
    }
}

/// A static friction limit: at least the kinetic level (stiction never below sliding
/// friction; equal is plain Coulomb friction with a stick mode).
fn static_limit(checks: &mut Checks, (s, fs): (&str, f64), (k, fc): (&str, f64)) {
    if fs < fc {
        checks.problem(
            &[s, k],
            format!("{s} must be at least {k} (static friction holds at least what sliding friction does), found {fs} < {fc}"),
        );
    }
}
