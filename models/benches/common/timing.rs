//! Timing shared by the benches that report numbers beside criterion's.

use std::time::{Duration, Instant};

/// Median wall time of `f` over enough calls to take ~0.5 s (at least 5): the median,
/// not the mean, as the machine is shared.
pub fn time_per_call(mut f: impl FnMut()) -> Duration {
    f();
    let started = Instant::now();
    let mut times = Vec::new();
    while times.len() < 5 || started.elapsed() < Duration::from_millis(500) {
        let call = Instant::now();
        f();
        times.push(call.elapsed());
    }
    times.sort_unstable();
    times[times.len() / 2]
}
