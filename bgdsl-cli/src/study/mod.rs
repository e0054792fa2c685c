//! Studies beyond one run: Monte Carlo sampling, quantile bands, and shards (`--shard
//! K/N`) with their manifests for `merge`.

pub mod bands;
pub mod distribution;
pub mod manifest;
pub mod shard;
