//! The bgdsl program as a library: the command line, scenario files, sweeps, run folders,
//! figures, `index.html` and FMU packaging, over any model written with `bond_graph!`.
#![warn(missing_docs)]
pub mod study;
