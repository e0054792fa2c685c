// The anchor is driven along x and y but pushed along z, so along z the damper must
// compute the stretch rate from the force while along x and y it computes the force:
// an R[3] acts on the whole vector and takes one causality. (Three scalar dampers
// behind a second splitter work: see tests/tests/splitter.rs; a TF with a plain-number
// ratio needs no such rewriting, it is taken apart by component.)
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Anchored {
        I[3] mass = 2.0;
        C[3] spring = 50.0;
        R[3] damper = 3.0;
        1 v;
        1 anchor;
        0 force;
        1 stretch;
        Split[3] guide;
        Sf drive = 0.3;
        Sf hold = 0.0;
        Se pushed = 1.5;

        drive -> guide.0;
        hold -> guide.1;
        pushed -> guide.2;
        guide -> anchor -> force -> v -> mass;
        force -> stretch -> { spring, damper };
    }
}

fn main() {}
