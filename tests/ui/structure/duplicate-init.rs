use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring;
        init spring.q = 0.01;
        init spring.q = 0.02;
    }
}

fn main() {}
