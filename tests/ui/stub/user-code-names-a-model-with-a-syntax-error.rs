use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    pub model Oscillator {
        Sf push = 1.0;
        C spring = 100.0;
        push -> spring;
        output x = spring.q
    }
}

fn main() {
    let model = Oscillator::default();
    let mut dx = [0.0; 1];
    model.derivatives(0.0, &[0.01], &mut dx);
    println!("{:?} {:?}", OscillatorParams::default(), dx);
}
