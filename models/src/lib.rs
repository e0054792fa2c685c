//! Models written with `bond_graph!`.
