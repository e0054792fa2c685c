use bgdsl_runtime::bond_graph;

bond_graph! {
    model Charger {
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring;
        init spring.p = 0.01;
    }

    model Shaker {
        Se push = 1.0;
        I mass = 1.0;
        1 v;
        push -> v -> mass;
        output speed = v.e;
    }
}

fn main() {}
