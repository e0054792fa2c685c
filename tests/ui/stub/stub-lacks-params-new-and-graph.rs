// Only the model's own error should appear. Today the stub has an empty params struct
// and no inherent items, so each use below is a follow-on error: E0560 (no field `k`),
// E0599 (`new`), E0599 (`GRAPH`). The declared parameter names are known even when the
// model has a mistake, so the stub could declare them; `new`, `N_STATES`, `GRAPH`,
// `OscillatorState`, `OscillatorOutputs` could be stubbed too.
use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    pub model Oscillator {
        param k = 100.0;
        Sf push = 1.0;
        C spring = k;
        push -> spring;
        init spring.p = 0.01;
        output x = spring.q;
    }
}

fn main() {
    let model = Oscillator::new(OscillatorParams { k: 3.0 });
    let mut dx = [0.0; 1];
    model.derivatives(0.0, &[0.0], &mut dx);
    println!("{}", Oscillator::GRAPH.model);
}
