//! `--shard K/N`: the K-th of N disjoint parts of a study's (or a sweep's) items.
//!
//! The items (sweep points in grid order, or Monte Carlo sample indices `0..M`) are cut
//! into N contiguous blocks of near-equal size: shard K (1-based, as Slurm's array
//! indices usually are) gets the indices `floor((K-1) M / N) .. floor(K M / N)`. The
//! blocks depend only on M, N and K, so every shard can run anywhere, in any order, and
//! be run again with the same result.

use core::fmt;
use core::ops::Range;
use core::str::FromStr;

/// One part of N.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Shard {
    /// Which part, 1-based: `1..=count`.
    pub index: usize,
    /// How many parts.
    pub count: usize,
}

impl Shard {
    /// The item indices of this shard when there are `items` items.
    pub fn range(self, items: usize) -> Range<usize> {
        // u128: `items * count` cannot overflow.
        let at = |k: usize| (k as u128 * items as u128 / self.count as u128) as usize;
        at(self.index - 1)..at(self.index)
    }

    /// Checks that every shard gets at least one item.
    ///
    /// # Errors
    ///
    /// A message for `--shard` when there are more shards than items.
    pub fn check_items(self, items: usize, what: &str) -> Result<(), String> {
        if self.count > items {
            Err(format!(
                "{} shards but only {items} {what}: every shard must get at least one; use \
                 at most {items} shards",
                self.count
            ))
        } else {
            Ok(())
        }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let usage = "expected K/N with 1 <= K <= N, e.g. `--shard 2/8` for the second of \
                     eight parts";
        let (k, n) = s.split_once('/').ok_or_else(|| format!("`{s}`: {usage}"))?;
        let number = |t: &str| t.trim().parse::<usize>().ok();
        match (number(k), number(n)) {
            (Some(index), Some(count)) if (1..=count).contains(&index) => {
                Ok(Shard { index, count })
            }
            (Some(0), Some(_)) => Err(format!(
                "`{s}`: shards are numbered from 1 (for Kubernetes' JOB_COMPLETION_INDEX, \
                 which starts at 0, pass $((JOB_COMPLETION_INDEX + 1))); {usage}"
            )),
            _ => Err(format!("`{s}`: {usage}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cover_every_item_once_in_order() {
        for items in [1, 2, 7, 10, 101] {
            for count in 1..=items.min(12) {
                let mut next = 0;
                for index in 1..=count {
                    let r = Shard { index, count }.range(items);
                    assert_eq!(r.start, next, "{index}/{count} of {items}");
                    assert!(!r.is_empty(), "{index}/{count} of {items}");
                    // Near-equal: sizes differ by at most one.
                    assert!(r.len() == items / count || r.len() == items / count + 1);
                    next = r.end;
                }
                assert_eq!(next, items);
            }
        }
    }

    #[test]
    fn parses_k_of_n_and_refuses_the_rest() {
        assert_eq!("3/8".parse(), Ok(Shard { index: 3, count: 8 }));
        assert_eq!(Shard { index: 3, count: 8 }.to_string(), "3/8");
        for bad in ["0/4", "5/4", "4", "a/b", "1/0", "-1/4", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        assert!("0/4"
            .parse::<Shard>()
            .unwrap_err()
            .contains("numbered from 1"));
        assert_eq!(
            Shard { index: 1, count: 5 }
                .check_items(3, "samples")
                .unwrap_err(),
            "5 shards but only 3 samples: every shard must get at least one; use at most 3 shards"
        );
    }
}
