use bgdsl_runtime::bond_graph;

bond_graph! {}

fn main() {}
