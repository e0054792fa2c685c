// A Rust keyword as a junction's name: one error at its declaration, with the fix
// (`r#loop`), and nothing else: the bonds and the output that name it still resolve.
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Loop {
        Se push = 1.0;
        I mass = 1.0;
        1 loop;
        push -> loop -> mass;
        output v = loop.f;
    }
}

fn main() {}
