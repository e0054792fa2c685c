use bgdsl_runtime::{bond_graph, Model};

bond_graph! {
    pub model Train {
        param m = 1000.0;
        Se push = 1.0;
        I engine = m;
        I wagon = 500.0;
        1 v;
        push -> v -> { engine, wagon };
    }
}

fn main() {
    let model = Train::new(TrainParams::default());
    let mut dx = [0.0; 2];
    model.derivatives(0.0, &[1.0, 0.5], &mut dx);
    println!("{} {:?} {:?}", Train::NAME, model.params(), dx);
}
