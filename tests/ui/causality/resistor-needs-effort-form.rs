use bgdsl_runtime::bond_graph;

bond_graph! {
    model Valve {
        Sf pump = 1.0;
        R orifice { f = e.abs().sqrt() };
        pump -> orifice;
    }
}

fn main() {}
