use bgdsl_runtime::bond_graph;

bond_graph! {
    submodel Mass(m, g) {
        I[3] body = m;
        Se[3] weight = bgdsl_runtime::multibond::vec3(0.0, -m * g, 0.0);
        1 v;
        weight -> v -> body;
    }

    model Drop {
        Mass ball(m = 1.0, mass = 2.0);
    }
}

fn main() {}
