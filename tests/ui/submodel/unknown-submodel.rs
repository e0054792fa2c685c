use bgdsl_runtime::bond_graph;

bond_graph! {
    model Arm {
        RigidBdy link(m = 1.0);
    }
}

fn main() {}
