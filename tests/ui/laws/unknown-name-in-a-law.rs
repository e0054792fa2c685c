// A misspelt parameter in a source's law, a misspelt element in an output, and a
// misspelt parameter in another parameter's default and in an initial condition: each
// reported by the macro at the name, with the nearest name of the model.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        param force = 1.0;
        param k = 100.0;
        param stiff = 2.0 * kk;
        Se push = forse;
        I mass = 1.0;
        C spring = k;
        1 v;
        push -> v -> { mass, spring };
        init spring.q = 0.1 * forc;
        output y = vv.f;
    }
}

fn main() {}
