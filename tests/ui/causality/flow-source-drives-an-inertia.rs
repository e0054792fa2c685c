// Wrong note: "Sf `drive` takes integral causality here first"; a source has no
// integral causality. Should read e.g. "note: Sf `drive` fixes its flow here".
use bgdsl_runtime::bond_graph;

bond_graph! {
    model Shaker {
        Sf drive = 1.0;
        I mass = 2.0;
        drive -> mass;
    }
}

fn main() {}
