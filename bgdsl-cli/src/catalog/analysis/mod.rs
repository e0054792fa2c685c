//! TEMPORARY (h3, until h2's CLI: lands): the analyses behind the catalogue.

pub mod fit;
pub mod periodic;
