bgdsl_runtime::bond_graph! {
    /// A chain of 10 rigid links joined by spring-damper joints.
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
        output y1 = b1.r.y;
    }
}
