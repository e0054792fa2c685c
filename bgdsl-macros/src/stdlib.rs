//! The standard submodels, written in the language itself and compiled with every
//! model. A model's own `submodel` of the same name takes precedence. Helper functions
//! are named by their full path, so the library works whatever the user imports.

use crate::flatten::SubmodelDef;

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
                "FrameCoupling"
            ]
        );
    }
}
