// The rigid-body chain of `bodies.rs` (`generate.sh rigid 420`, the same text) declared
// in a function body, for `a_chunked_model_in_a_function_body`.
/// The derivatives of the function-local chain at `x`.
fn derivatives_in_a_function(t: f64, x: &[f64]) -> Vec<f64> {
    bgdsl_runtime::bond_graph! {
        /// A chain of 20 rigid links joined by spring-damper joints.
        pub model Bodies {
            param m = 0.5; param l = 0.2; param k = 1.0e4; param c = 5.0; param g = 9.81;
            Ground ground();
            RigidBody b1(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((1.0 - 0.5) * l, 0.0, 0.0));
            Point b1_a(body = b1, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b1_b(body = b1, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j1(a = ground.v, b = b1_a.v, k = k, c = c);
            RigidBody b2(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((2.0 - 0.5) * l, 0.0, 0.0));
            Point b2_a(body = b2, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b2_b(body = b2, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j2(a = b1_b.v, b = b2_a.v, k = k, c = c);
            RigidBody b3(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((3.0 - 0.5) * l, 0.0, 0.0));
            Point b3_a(body = b3, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b3_b(body = b3, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j3(a = b2_b.v, b = b3_a.v, k = k, c = c);
            RigidBody b4(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((4.0 - 0.5) * l, 0.0, 0.0));
            Point b4_a(body = b4, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b4_b(body = b4, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j4(a = b3_b.v, b = b4_a.v, k = k, c = c);
            RigidBody b5(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((5.0 - 0.5) * l, 0.0, 0.0));
            Point b5_a(body = b5, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b5_b(body = b5, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j5(a = b4_b.v, b = b5_a.v, k = k, c = c);
            RigidBody b6(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((6.0 - 0.5) * l, 0.0, 0.0));
            Point b6_a(body = b6, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b6_b(body = b6, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j6(a = b5_b.v, b = b6_a.v, k = k, c = c);
            RigidBody b7(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((7.0 - 0.5) * l, 0.0, 0.0));
            Point b7_a(body = b7, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b7_b(body = b7, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j7(a = b6_b.v, b = b7_a.v, k = k, c = c);
            RigidBody b8(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((8.0 - 0.5) * l, 0.0, 0.0));
            Point b8_a(body = b8, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b8_b(body = b8, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j8(a = b7_b.v, b = b8_a.v, k = k, c = c);
            RigidBody b9(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((9.0 - 0.5) * l, 0.0, 0.0));
            Point b9_a(body = b9, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b9_b(body = b9, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j9(a = b8_b.v, b = b9_a.v, k = k, c = c);
            RigidBody b10(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((10.0 - 0.5) * l, 0.0, 0.0));
            Point b10_a(body = b10, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b10_b(body = b10, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j10(a = b9_b.v, b = b10_a.v, k = k, c = c);
            RigidBody b11(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((11.0 - 0.5) * l, 0.0, 0.0));
            Point b11_a(body = b11, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b11_b(body = b11, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j11(a = b10_b.v, b = b11_a.v, k = k, c = c);
            RigidBody b12(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((12.0 - 0.5) * l, 0.0, 0.0));
            Point b12_a(body = b12, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b12_b(body = b12, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j12(a = b11_b.v, b = b12_a.v, k = k, c = c);
            RigidBody b13(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((13.0 - 0.5) * l, 0.0, 0.0));
            Point b13_a(body = b13, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b13_b(body = b13, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j13(a = b12_b.v, b = b13_a.v, k = k, c = c);
            RigidBody b14(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((14.0 - 0.5) * l, 0.0, 0.0));
            Point b14_a(body = b14, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b14_b(body = b14, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j14(a = b13_b.v, b = b14_a.v, k = k, c = c);
            RigidBody b15(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((15.0 - 0.5) * l, 0.0, 0.0));
            Point b15_a(body = b15, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b15_b(body = b15, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j15(a = b14_b.v, b = b15_a.v, k = k, c = c);
            RigidBody b16(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((16.0 - 0.5) * l, 0.0, 0.0));
            Point b16_a(body = b16, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b16_b(body = b16, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j16(a = b15_b.v, b = b16_a.v, k = k, c = c);
            RigidBody b17(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((17.0 - 0.5) * l, 0.0, 0.0));
            Point b17_a(body = b17, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b17_b(body = b17, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j17(a = b16_b.v, b = b17_a.v, k = k, c = c);
            RigidBody b18(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((18.0 - 0.5) * l, 0.0, 0.0));
            Point b18_a(body = b18, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b18_b(body = b18, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j18(a = b17_b.v, b = b18_a.v, k = k, c = c);
            RigidBody b19(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((19.0 - 0.5) * l, 0.0, 0.0));
            Point b19_a(body = b19, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b19_b(body = b19, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j19(a = b18_b.v, b = b19_a.v, k = k, c = c);
            RigidBody b20(m = m, J = ::bgdsl_runtime::multibond::box_inertia(m, l, 0.01, 0.01), g = g,
                R0 = ::bgdsl_runtime::multibond::Matrix3::identity(), r0 = ::bgdsl_runtime::multibond::vec3((20.0 - 0.5) * l, 0.0, 0.0));
            Point b20_a(body = b20, at = ::bgdsl_runtime::multibond::vec3(-0.5 * l, 0.0, 0.0));
            Point b20_b(body = b20, at = ::bgdsl_runtime::multibond::vec3(0.5 * l, 0.0, 0.0));
            Coupling j20(a = b19_b.v, b = b20_a.v, k = k, c = c);
            output y1 = b1.r.y;
        }
    }
    let mut dx = vec![0.0; x.len()];
    Bodies::default().derivatives::<f64>(t, x, &mut dx);
    dx
}
