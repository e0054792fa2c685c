#!/usr/bin/env bash
# Writes a `bond_graph!` chain model with about STATES states to stdout, for the sizing
# benchmark (run.sh) and its correctness test.
#
#   models/benches/sizing/generate.sh scalar 2000   # model Chain: 1,000 cells, 2,000 states
#   models/benches/sizing/generate.sh rigid 2100    # model Bodies: 100 bodies, 2,100 states
#
# scalar: a force on a chain of cells; cell i is a mass (1 v_i, I m_i) tied to the next
#   by a spring and a damper in parallel (0 n_i, 1 d_i, C k_i, R r_i): 2 states a cell.
#   LOSSLESS=1 leaves out the dampers and the force (the energy is then conserved).
# rigid: the standard library's RigidBody (18 states), two Points on it and a Coupling
#   (spring-damper joint, 3 states) to the previous body's far point (the first to the
#   ground), as the flagship joins its links: 21 states a body.
set -euo pipefail

kind="${1:?usage: generate.sh scalar|rigid STATES}"
states="${2:?usage: generate.sh scalar|rigid STATES}"

case "$kind" in
scalar)
    cells=$(((states + 1) / 2))
    awk -v cells="$cells" -v lossless="${LOSSLESS:-0}" 'BEGIN {
        print "bgdsl_runtime::bond_graph! {"
        print "    /// A chain of " cells " mass-spring-damper cells."
        print "    pub model Chain {"
        print "        param m = 1.0; param k = 100.0; param c = 0.5; param force = 1.0;"
        if (!lossless) {
            print "        Se source = force * (3.0 * t).sin();"
            print "        R ground = c;"
            print "        source -> v1; v1 -> ground;"
        }
        for (i = 1; i <= cells; i++) {
            w = 1 + (i % 7) * 0.125
            line = sprintf("        1 v%d; I m%d = m * %.3f; 0 n%d; C k%d = k / %.3f;", i, i, w, i, i, w)
            if (lossless) {
                line = line sprintf(" v%d -> { m%d, n%d }; n%d -> k%d;", i, i, i, i, i)
            } else {
                line = line sprintf(" 1 d%d; R r%d = c * %.3f; v%d -> { m%d, n%d }; n%d -> d%d -> { k%d, r%d };", i, i, w, i, i, i, i, i, i, i)
            }
            print line
            if (i < cells) print sprintf("        n%d -> v%d;", i, i + 1)
            if (lossless) print sprintf("        init m%d.p = %.3f;", i, (i % 5) * 0.25 - 0.5)
        }
        print "        output x1 = k1.q;"
        print "    }"
        print "}"
    }'
    ;;
rigid)
    bodies=$(((states + 20) / 21))
    awk -v bodies="$bodies" 'BEGIN {
        mb = "::bgdsl_runtime::multibond"
        print "bgdsl_runtime::bond_graph! {"
        print "    /// A chain of " bodies " rigid links joined by spring-damper joints."
        print "    pub model Bodies {"
        print "        param m = 0.5; param l = 0.2; param k = 1.0e4; param c = 5.0; param g = 9.81;"
        print "        Ground ground();"
        for (i = 1; i <= bodies; i++) {
            print sprintf("        RigidBody b%d(m = m, J = %s::box_inertia(m, l, 0.01, 0.01), g = g,", i, mb)
            print sprintf("            R0 = %s::Matrix3::identity(), r0 = %s::vec3((%d.0 - 0.5) * l, 0.0, 0.0));", mb, mb, i)
            print sprintf("        Point b%d_a(body = b%d, at = %s::vec3(-0.5 * l, 0.0, 0.0));", i, i, mb)
            print sprintf("        Point b%d_b(body = b%d, at = %s::vec3(0.5 * l, 0.0, 0.0));", i, i, mb)
            prev = (i == 1) ? "ground.v" : sprintf("b%d_b.v", i - 1)
            print sprintf("        Coupling j%d(a = %s, b = b%d_a.v, k = k, c = c);", i, prev, i)
        }
        print "        output y1 = b1.r.y;"
        print "    }"
        print "}"
    }'
    ;;
*)
    echo "generate.sh: unknown kind $kind (scalar or rigid)" >&2
    exit 2
    ;;
esac
