use bgdsl_runtime::bond_graph;

bond_graph! {
    model Lever {
        Sf push = 1.0;
        TF lever = 2.0;
        C spring = 100.0;
        I mass = 1.0;
        push -> lever -> { spring, mass };
    }
}

fn main() {}
