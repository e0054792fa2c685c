//! The standard submodels, written in the language itself and compiled with every
//! model. A model's own `submodel` of the same name takes precedence. Helper functions
//! are named by their full path, so the library works whatever the user imports.

use crate::flatten::SubmodelDef;

/// The name of the standard library's rigid body, whose instances are a model's
/// [`BODIES`](https://docs.rs/bgdsl-runtime): states `R` (orientation) and `r` (position).
pub const RIGID_BODY: &str = "RigidBody";

/// The standard library's text.
pub const TEXT: &str = r#"
    /// A rigid body in 3-D, as the seed paper models a link: translational momentum p
    /// with v = p / m, angular momentum h in frame 0 with w = (R J Rᵀ)⁻¹ h, orientation
    /// R (dR/dt = skew(w) R) and centre-of-mass position r (dr/dt = v), its weight
    /// m g along -Y0. `J` is the vector of principal inertias about the centre of mass
    /// in the body frame. Ports: `v` (the centre of mass's velocity) and `w` (the
    /// angular velocity), both 1-junctions; states `R`, `r`, `translation.p` (momentum)
    /// and `rotation.p` (angular momentum). (Elements here are never named `e`, `f`,
    /// `q` or `p`: those are the laws' own variables.) Units are SI: the states are in
    /// 1 (a rotation matrix), m, kg·m/s and kg·m²/s.
    submodel RigidBody(m, J, R0, r0, g) {
        /// orientation: body frame to frame 0
        state R: Matrix3 = R0 in "1";
        der R = ::bgdsl_runtime::multibond::skew(w.f) * R;
        /// centre-of-mass position in frame 0
        state r: Vector3 = r0 in "m";
        der r = v.f;
        /// momentum in frame 0
        I[3] translation = m, p in "kg·m/s";
        /// angular momentum about the centre of mass in frame 0
        I[3] rotation {
            f = R * ::bgdsl_runtime::multibond::vec3(1.0 / J.x, 1.0 / J.y, 1.0 / J.z)
                .component_mul(&(R.transpose() * p))
        }, p in "kg·m²/s";
        Se[3] weight = ::bgdsl_runtime::multibond::vec3(0.0, -m * g, 0.0);
        1 v;
        1 w;
        weight -> v -> translation;
        w -> rotation;
    }

    /// A point of a rigid body at the body-frame vector `at` from its centre of mass.
    /// Its velocity v + w × (R at) is the common flow of its port `v`; the MTF's effort
    /// relation turns a force F there into the torque (R at) × F on the body.
    submodel Point(body, at) {
        MTF arm = -::bgdsl_runtime::multibond::skew(body.R * at);
        0 sum;
        1 v;
        body.v -> sum;
        body.w -> arm -> sum;
        sum -> v;
    }

    /// A point of a rigid body given by its offset from the centre of mass in frame 0
    /// (it may move over the body, like the rocker's point under the crank pin).
    submodel OffsetPoint(body, offset) {
        MTF arm = -::bgdsl_runtime::multibond::skew(offset);
        0 sum;
        1 v;
        body.v -> sum;
        body.w -> arm -> sum;
        sum -> v;
    }

    /// A fixed point: zero velocity. Its port `v` takes couplings to the ground.
    submodel Ground() {
        Sf[3] fixed = ::bgdsl_runtime::multibond::vec3(0.0, 0.0, 0.0);
        1 v;
        fixed -> v;
    }

    /// A spring-damper joint between two ports `a` and `b` (point velocities, or
    /// angular velocities for a rotational joint). `spring.q` is the integral of
    /// a − b in frame 0; k and c are numbers or 3×3 matrices. The joint's force
    /// `spring.e + damper.e` acts on b, its opposite on a. (No unit on `spring.q`:
    /// it is in m between points, in rad between angular velocities.)
    submodel Coupling(a, b, k, c) {
        0 rel;
        1 d;
        /// deflection: the integral of a − b in frame 0
        C[3] spring = k;
        R[3] damper = c;
        a -> rel -> b;
        rel -> d -> { spring, damper };
    }

    /// A spring-damper joint whose laws act in a moving frame with rotation matrix
    /// `frame` (frame → frame 0), like a slider's guide on a rocking arm: the relative
    /// velocity is turned into the frame, `spring.q` integrates it there, and the
    /// force is turned back.
    submodel FrameCoupling(a, b, frame, k, c) {
        0 rel;
        MTF to_frame = frame.transpose(), inverse = frame;
        1 d;
        /// deflection: the integral of a − b in the moving frame
        C[3] spring = k;
        R[3] damper = c;
        a -> rel -> b;
        rel -> to_frame -> d -> { spring, damper };
    }

    /// An electrical switch between two nodes `a` and `b` (0-junctions: their efforts
    /// are the node voltages): a resistor with two laws chosen by the mode `closed`,
    /// `e = r_on f` (closed) and `f = g_off e` (open), where `e` is the voltage from `a`
    /// to `b` and `f` the current from `a` to `b` through the branch `branch` (a
    /// 1-junction). It closes when `control` rises through 0 and opens when it falls
    /// through 0 (events `close`, `open`); `control` is any expression of the model
    /// (a clock, a comparator, a controller's output). The user supplies `r_on > 0`
    /// (the closed law is also used as `f = e / r_on` when the nodes fix the voltage,
    /// the usual case) and `g_off >= 0` (0: an ideal open switch, usable only where
    /// the nodes fix the voltage), and `closed0`, the mode at the start: an indicator
    /// starts no event at t0, so a switch whose control is already positive must start
    /// closed. Element `law` (an R); mode `closed`. An indicator's sign is compared
    /// at step ends and a few points inside: where the control can cross 0 twice
    /// while the states barely move (an open switch on a clock), give the integrator
    /// a largest step below the shortest interval between crossings.
    submodel Switch(a, b, control, r_on, g_off, closed0 = false) {
        /// conducting (r_on) rather than blocking (g_off)
        mode closed: bool = closed0;
        1 branch;
        R law {
            e = if closed { r_on * f } else { f / g_off },
            f = if closed { e / r_on } else { g_off * e },
        };
        a -> branch -> b;
        branch -> law;
        /// The control rises through 0.
        when close: control > 0.0 { closed = true; }
        /// The control falls through 0.
        when open: control < 0.0 { closed = false; }
    }

    /// An ideal diode between two nodes `a` (anode) and `b` (cathode), as
    /// [`Switch`] whose control is its own voltage `law.e` from anode to cathode: it
    /// conducts by `e = r_on f` and blocks by `f = g_off e`. Both laws pass through the
    /// origin with positive slope, so the voltage and the current have one sign and the
    /// voltage crossing 0 is the instant either would cross it: it switches on when the
    /// voltage rises through 0 (event `conduct`) and off when it falls through 0
    /// (`block`).
    /// With the nodes fixing the voltage (a source or a capacitor at each node, the
    /// usual case) the diode computes its current, `f = e / r_on` or `g_off e`, and
    /// `g_off = 0` is an ideal block. The user supplies `r_on > 0` (the forward path's
    /// resistance: a source's internal resistance can be folded into it) and `on0`,
    /// the mode at the start (an indicator starts no event at t0: a diode whose
    /// voltage starts at 0 and rises must start on). Element `law` (an R: `law.e` the
    /// voltage, `branch.f` the current); mode `on`. While it blocks, the circuit's
    /// states may not see the source that drives its voltage: give the integrator a
    /// largest step below the shortest conduction window, or it may step over one
    /// (both crossings inside a step leave the signs at its ends alike).
    submodel Diode(a, b, r_on, g_off = 0.0, on0 = false) {
        /// conducting
        mode on: bool = on0;
        1 branch;
        R law {
            e = if on { r_on * f } else { f / g_off },
            f = if on { e / r_on } else { g_off * e },
        };
        a -> branch -> b;
        branch -> law;
        /// The voltage rises through 0.
        when conduct: law.e > 0.0 { on = true; }
        /// The voltage falls through 0.
        when block: law.e < 0.0 { on = false; }
    }

    /// An impact with restitution on a stop, for a body that reaches it: when `gap`
    /// (any expression of the model, positive while the body is clear of the stop)
    /// falls through 0 (event `hit`), the body's momentum `body.p` (an I element,
    /// handed by name) is reinitialised to `-restitution · body.p` (Newton's law of
    /// restitution, 0 <= restitution <= 1; the energy it removes is in the event's
    /// energy change). An impact whose rebound speed `restitution · |body.f|` is below
    /// `v_rest` comes to rest instead (Zeno's cascade of ever shorter bounces, cut
    /// where the physics no longer resolves it): mode `resting`, momentum 0, and the
    /// stop's reaction `held` acts on the body's junction `at` (a 1-junction with the
    /// body's velocity) through the source `support`. `held` is the force (along `at`'s
    /// positive direction) that keeps the body at rest, which the model supplies
    /// (a ball's weight `m * g`); the body rests only if that force pushes away from
    /// the stop, `dir · held > 0`, where `dir` is +1 when the gap opens as `at` moves
    /// positively and -1 otherwise; it lifts off when `dir · held` falls through 0
    /// (event `lift`, watched only while resting). `v_rest = 0` never rests (a run of ever shorter bounces then ends
    /// with the runtime's chattering error).
    submodel Impact(at, body, gap, dir, restitution, v_rest = 0.0, held = 0.0) {
        /// at rest on the stop
        mode resting: bool = false;
        Se support = if resting { held } else { 0.0 };
        support -> at;
        /// The gap closes.
        when hit: gap < 0.0 {
            if restitution * body.f.abs() < v_rest && dir * held > 0.0 {
                resting = true;
                reinit body.p = 0.0;
            } else {
                reinit body.p = -restitution * body.p;
            }
        }
        /// The support would have to pull.
        when lift: (if resting { dir * held } else { 1.0 }) < 0.0 { resting = false; }
    }

    /// A one-sided spring-damper contact at a stop: in mode `touching` a spring of
    /// stiffness `k` and a damper `c` act on the junction `at` (a 1-junction with the
    /// body's velocity), and nothing otherwise. Contact begins when `gap` (any
    /// expression, positive while clear) falls through 0 (event `touch`), where the
    /// spring's deflection `spring.q` is set to `dir · gap` (≈ 0): in contact it is the
    /// displacement of `at` from the stop's surface and the force on `at` is
    /// `-(k q + c v)`. It ends when that force would pull, `dir (k spring.q + c at.f)`
    /// rising through 0 (event `release`, watched only in contact): a contact only
    /// pushes. `dir` is +1 when the
    /// gap opens as `at` moves positively, -1 otherwise. Elements `spring` (a C; its
    /// deflection follows `at` in both modes, its energy counts only in contact, and
    /// the energy the release drops is that event's energy change) and `damper` (an R).
    submodel Contact(at, gap, dir, k, c) {
        /// pressed against the stop
        mode touching: bool = false;
        /// the contact's deflection along `at` (meaningful in contact)
        C spring { e = if touching { k * q } else { 0.0 } };
        R damper { e = if touching { c * f } else { 0.0 } };
        at -> { spring, damper };
        /// The gap closes.
        when touch: gap < 0.0 {
            touching = true;
            reinit spring.q = dir * gap;
        }
        /// The contact force would pull.
        when release: (if touching { dir * (k * spring.q + c * at.f) } else { -1.0 }) > 0.0 {
            touching = false;
        }
    }

    /// Kinetic Coulomb friction between two ports `a` and `b` (1-junctions: velocities,
    /// or angular velocities): a force of magnitude `fc` against the slip velocity
    /// `law.f = a − b`, its direction the mode `forward` (true: slip positive, the
    /// force `law.e = fc` drags `b` forward and holds `a` back). The mode switches when
    /// the slip crosses 0 (events `backward` and `ahead`). No sticking: where the slip
    /// would stay at 0 the direction flips at every step and the run ends with the
    /// runtime's chattering error; use [`StickSlip`] there. The user supplies
    /// `forward0`, the sign of the initial slip (true for positive). Element `law`
    /// (an R: its power is the friction loss).
    submodel CoulombFriction(a, b, fc, forward0 = true) {
        /// slipping with a − b > 0
        mode forward: bool = forward0;
        0 rel;
        R law { e = if forward { fc } else { -fc } };
        a -> rel -> b;
        rel -> law;
        /// The slip falls through 0.
        when backward: law.f < 0.0 { forward = false; }
        /// The slip rises through 0.
        when ahead: law.f > 0.0 { forward = true; }
    }

    /// Coulomb friction with stiction between two ports `a` and `b` (1-junctions):
    /// slipping, the force `law.e` on `b` is `fc` against the slip `law.f = a − b`
    /// (mode `forward`, as [`CoulombFriction`]); stuck (mode `stuck`), it is `held`,
    /// the force on `b` that keeps the slip at 0, which the model supplies (it is the
    /// constraint force: for a mass on a belt, minus the other forces on the mass plus
    /// its mass times the belt's acceleration). When the slip crosses 0 (events
    /// `backward`, watched only while slipping forward, and `ahead`, only while
    /// slipping backward) the contact sticks if `|held| <= fs`, and otherwise the slip
    /// reverses; stuck, it breaks away when `held` leaves [-fs, fs] (events
    /// `break_ahead`, `break_back`, watched only while stuck), slipping in the
    /// direction `held` pointed. A stuck contact keeps the slip it had at the event
    /// (of the order of the event time tolerance times the slip's acceleration), so
    /// a slip that starts at a breakaway may cross 0 once just after it: in the
    /// direction it breaks away to, which is not watched. The user supplies `fs >= fc`,
    /// `held`, and the modes at the start (`stuck0`, `forward0`). Element `law` (an
    /// R: its power is the friction loss, ≈ 0 while stuck).
    submodel StickSlip(a, b, fc, fs, held, stuck0 = false, forward0 = true) {
        /// stuck: no slip, the force is `held`
        mode stuck: bool = stuck0;
        /// slipping with a − b > 0
        mode forward: bool = forward0;
        0 rel;
        R law { e = if stuck { held } else if forward { fc } else { -fc } };
        a -> rel -> b;
        rel -> law;
        /// The slip falls through 0.
        when backward: (if stuck || !forward { 1.0 } else { law.f }) < 0.0 {
            if held.abs() <= fs { stuck = true; } else { forward = false; }
        }
        /// The slip rises through 0.
        when ahead: (if stuck || forward { -1.0 } else { law.f }) > 0.0 {
            if held.abs() <= fs { stuck = true; } else { forward = true; }
        }
        /// The force needed to stick exceeds fs.
        when break_ahead: (if stuck { held - fs } else { -1.0 }) > 0.0 {
            stuck = false;
            forward = true;
        }
        /// The force needed to stick falls below -fs.
        when break_back: (if stuck { held + fs } else { 1.0 }) < 0.0 {
            stuck = false;
            forward = false;
        }
    }

    /// A friction clutch between two shafts `a` and `b` (1-junctions: angular
    /// velocities): [`StickSlip`] with torques, slipping at the torque `tk` and locked
    /// while the torque `held` that keeps both shafts at one speed (which the model
    /// supplies: for inertias J1, J2 driven by torques T1, T2, `(J2 T1 − J1 T2) /
    /// (J1 + J2)`) stays within `ts`. It engages when the speeds match. Instance
    /// `plates` (its modes `plates.stuck`, `plates.forward`, its R `plates.law`).
    submodel Clutch(a, b, tk, ts, held, locked0 = false, forward0 = true) {
        StickSlip plates(a = a, b = b, fc = tk, fs = ts, held = held,
            stuck0 = locked0, forward0 = forward0);
    }
"#;

/// The standard submodels, parsed.
pub fn submodels() -> syn::Result<Vec<SubmodelDef>> {
    struct Library(Vec<SubmodelDef>);
    impl syn::parse::Parse for Library {
        fn parse(input: syn::parse::ParseStream) -> syn::Result<Self> {
            let mut defs = Vec::new();
            while !input.is_empty() {
                input.call(syn::Attribute::parse_outer)?;
                input.parse::<crate::syntax::kw::submodel>()?;
                defs.push(input.parse()?);
            }
            Ok(Library(defs))
        }
    }
    syn::parse_str::<Library>(TEXT).map(|library| library.0)
}

#[cfg(test)]
mod should {
    #[test]
    fn parse() {
        let names: Vec<String> = super::submodels()
            .unwrap()
            .iter()
            .map(|d| d.name.to_string())
            .collect();
        assert_eq!(
            names,
            [
                "RigidBody",
                "Point",
                "OffsetPoint",
                "Ground",
                "Coupling",
                "FrameCoupling",
                "Switch",
                "Diode",
                "Impact",
                "Contact",
                "CoulombFriction",
                "StickSlip",
                "Clutch"
            ]
        );
    }
}
