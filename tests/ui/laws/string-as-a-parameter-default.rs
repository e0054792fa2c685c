use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param k = "stiff";
        Sf push = 1.0;
        C spring = k;
        push -> spring;
        output x = spring.q;
    }
}

fn main() {}
