use bgdsl_runtime::bond_graph;

bond_graph! {
    model Tanks {
        Sf inflow = 1.0;
        C tank_a = 2.0;
        C tank_b = 3.0;
        0 level;
        inflow -> level -> { tank_a, tank_b };
    }
}

fn main() {}
