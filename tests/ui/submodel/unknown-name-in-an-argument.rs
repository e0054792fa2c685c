// A misspelt parameter passed to a submodel instance: reported by the macro with a
// did-you-mean, like one written in a law.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Pair {
        param stiffness = 1000.0;
        Ground ground();
        Ground other();
        Coupling joint(a = ground.v, b = other.v, k = stifness, c = 1.0);
    }
}

fn main() {}
