// The error is right; the note is not: "Se `push` takes integral causality here first".
// A source has no integral causality; the note should read "Se `push` fixes its effort here".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Charger {
        Se push = 1.0;
        C spring = 100.0;
        push -> spring;
        output x = spring.q;
    }
}

fn main() {}
