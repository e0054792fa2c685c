// Same mechanism as error-inside-braces-hides-other-errors, in a fan-out group.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Oscillator {
        Se push = 1.0;
        I mass = 1.0;
        C spring = 100.0;
        1 v;
        push -> v -> { mass spring };
        output x = spring.q;
    }
}

fn main() {}
