//! `Model::BODIES`: one entry per instance of the standard library's `RigidBody`, named
//! by the instance's path and pointing at the states an animation reads (`R_11` and
//! `r_x`, the first of the orientation's nine and the position's three).

use bgdsl_runtime::multibond::{box_inertia, rot_z, vec3};
use bgdsl_runtime::{bond_graph, BodyInfo, Model};
use models::quick_return::torque_driven::QuickReturnTorque;
use models::quick_return::QuickReturn;
use models::quick_return_hybrid::{QuickReturnEndStop, QuickReturnFriction};

bond_graph! {
    /// Two bars inside an arm instance and one at the top level: bodies nest.
    submodel Arm(m, g) {
        RigidBody upper(m = m, J = box_inertia(m, 0.2, 0.01, 0.01), g = g,
            R0 = rot_z(0.0), r0 = vec3(0.1, 0.0, 0.0));
        RigidBody lower(m = m, J = box_inertia(m, 0.2, 0.01, 0.01), g = g,
            R0 = rot_z(0.0), r0 = vec3(0.3, 0.0, 0.0));
        Coupling elbow(a = upper.v, b = lower.v, k = 1.0e4, c = 10.0);
    }

    pub model NestedBodies {
        param m = 0.5 in "kg";
        param g = 9.81 in "m/s²";
        RigidBody base(m = m, J = box_inertia(m, 0.1, 0.1, 0.1), g = g,
            R0 = rot_z(0.0), r0 = vec3(0.0, 0.0, 0.0));
        Arm arm(m = m, g = g);
        Coupling shoulder(a = base.v, b = arm.upper.v, k = 1.0e4, c = 10.0);
    }
}

bond_graph! {
    /// A model's own `RigidBody` shadows the library's: it is not one of BODIES.
    submodel RigidBody(m) {
        I mass = m;
        1 v;
        v -> mass;
    }

    pub model ShadowedBody {
        RigidBody puck(m = 1.0);
    }
}

/// Each body's entry points at `<body>.R_11` and `<body>.r_x`, and the nine and three
/// states from there are its orientation (column by column) and its position.
fn assert_points_at_its_states<M: Model>(expected: &[&str]) {
    let names: Vec<&str> = M::BODIES.iter().map(|b| b.name).collect();
    assert_eq!(names, expected, "{}", M::NAME);
    for body in M::BODIES {
        let states = M::STATE_NAMES;
        let orientation: Vec<String> = ["11", "21", "31", "12", "22", "32", "13", "23", "33"]
            .iter()
            .map(|ij| format!("{}.R_{ij}", body.name))
            .collect();
        assert_eq!(
            &states[body.orientation..body.orientation + 9],
            orientation.as_slice(),
            "{}: {}",
            M::NAME,
            body.name
        );
        let position: Vec<String> = ["x", "y", "z"]
            .iter()
            .map(|c| format!("{}.r_{c}", body.name))
            .collect();
        assert_eq!(
            &states[body.position..body.position + 3],
            position.as_slice(),
            "{}: {}",
            M::NAME,
            body.name
        );
    }
}

const LINKS: [&str; 5] = ["crank", "slider", "rocker", "rod", "output_slider"];

#[test]
fn name_the_flagships_five_links() {
    assert_points_at_its_states::<QuickReturn>(&LINKS);
    assert_points_at_its_states::<QuickReturnTorque>(&LINKS);
    assert_points_at_its_states::<QuickReturnEndStop>(&LINKS);
    assert_points_at_its_states::<QuickReturnFriction>(&LINKS);
}

/// At the start, the poses read through BODIES are the assembly the spec fixes: the
/// crank at θ0 = π/2 about Z0 with its centre of mass half a crank length up Y0.
#[test]
fn read_the_flagships_assembly_through_bodies() {
    let model = QuickReturn::default();
    let mut x = vec![0.0; QuickReturn::N_STATES];
    model.initial_state(&mut x);
    let crank: &BodyInfo = &QuickReturn::BODIES[0];
    let r = crank.orientation_of(&x);
    let expected = rot_z(core::f64::consts::FRAC_PI_2);
    assert_eq!(r.as_slice(), expected.as_slice());
    let p = crank.position_of(&x);
    assert!((p[0] - 0.0).abs() < 1e-15 && (p[1] - 0.1).abs() < 1e-15 && p[2] == 0.0);
}

#[test]
fn name_nested_bodies_by_their_path() {
    assert_points_at_its_states::<NestedBodies>(&["base", "arm.upper", "arm.lower"]);
}

#[test]
fn give_none_for_a_shadowed_rigid_body_or_a_model_without_bodies() {
    assert!(ShadowedBody::BODIES.is_empty());
    assert!(models::DcMotor::BODIES.is_empty());
}
