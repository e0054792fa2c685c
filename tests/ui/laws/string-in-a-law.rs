use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Sf push = 1.0;
        C spring { e = 100.0 * q + "stiff" };
        push -> spring;
        output x = spring.q;
    }
}

fn main() {}
