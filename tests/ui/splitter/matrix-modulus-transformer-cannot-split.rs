// A lever with a matrix ratio between the guide and the anchor: along x it must pass
// the guide's flow on, along z the guide's push, but a TF whose modulus may be a matrix
// acts on the whole vector and takes one causality. (With a plain-number ratio,
// `TF lever = 2.5;`, it is taken apart by component and compiles: see
// tests/tests/splitter.rs.)
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Levered {
        I[3] mass = 2.0;
        C[3] spring = 50.0;
        R[3] damper = 3.0;
        MTF lever = diag3(2.5, 2.5, 2.5);
        1 v;
        1 anchor;
        0 force;
        Split[3] guide;
        Sf drive = 0.3;
        Sf hold = 0.0;
        Se pushed = 1.5;

        drive -> guide.0;
        hold -> guide.1;
        pushed -> guide.2;
        guide -> lever -> anchor -> force -> v -> mass;
        force -> { spring, damper };
    }
}

fn main() {}
