use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    pub model Oscillator {
        Sf push = 1.0;
        C spring { e = 100.0 * q + p };
        push -> spring;
        output x = spring.q;
    }
}

fn main() {
    let params: OscillatorParams = Default::default();
    let model = Oscillator::new(params);
    let mut dx = [0.0; 1];
    model.derivatives(0.0, &[0.01], &mut dx);
    assert_eq!(Oscillator::STATE_NAMES.len(), 0);
}
