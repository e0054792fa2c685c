//! `shard.yaml`: what a shard folder holds, and the checks `merge` makes on a set of
//! them before joining anything.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::shard::Shard;

/// The manifest's file name in a shard folder.
pub const FILE_NAME: &str = "shard.yaml";

/// What a shard folder holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The program and its version that ran it, e.g. `models 0.1.0`.
    pub program: String,
    /// The study's hash ([`study_hash`]): shards join only with the same hash.
    pub study: String,
    /// `sweep` or `monte_carlo`.
    pub kind: String,
    /// The shard, 1-based.
    pub shard: usize,
    /// The number of shards.
    pub shards: usize,
    /// The number of items (points or samples) of the whole study.
    pub items: usize,
    /// The first item index of this shard (0-based, included).
    pub first: usize,
    /// The item index after its last (excluded).
    pub end: usize,
    /// Whether every item ran (a shard folder committed as `.partial` says false).
    pub complete: bool,
    /// What the program needs to write the joined files besides the numbers (titles,
    /// names, units), as it chooses.
    #[serde(default)]
    pub details: serde_yaml::Value,
}

impl Manifest {
    /// The shard as `K/N`.
    pub fn shard(&self) -> Shard {
        Shard {
            index: self.shard,
            count: self.shards,
        }
    }

    /// Reads `dir/shard.yaml`.
    ///
    /// # Errors
    ///
    /// A message naming the folder: no manifest (not a shard folder), or not readable.
    pub fn read(dir: &Path) -> Result<Self, String> {
        let path = dir.join(FILE_NAME);
        let text = std::fs::read_to_string(&path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                format!(
                    "{}: not a shard folder (no {FILE_NAME}); give the folders that `run \
                     ... --shard K/N` wrote",
                    dir.display()
                )
            } else {
                format!("{}: cannot read it: {e}", path.display())
            }
        })?;
        serde_yaml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The manifest as YAML, with a comment saying what it is.
    pub fn to_yaml(&self) -> String {
        let body = serde_yaml::to_string(self).unwrap_or_default();
        format!(
            "# One shard of a study: items {}..{} (end excluded) of {}. Join the {} shards \
             with `merge`.\n{body}",
            self.first, self.end, self.items, self.shards
        )
    }
}

/// The hash that identifies a study: SHA-256 (hex) of the program's name and version
/// and the canonical text of the resolved study (every setting that changes a result;
/// not the output folder, not the shard).
pub fn study_hash(program: &str, canonical: &str) -> String {
    let mut hasher = Sha256::new();
    hasher.update(program.as_bytes());
    hasher.update(b"\n");
    hasher.update(canonical.as_bytes());
    hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Checks that `shards` (folder, manifest) are all the shards of one complete study,
/// each once; returns them in shard order.
///
/// # Errors
///
/// Every problem found, one message each, naming the folders: shards of different
/// studies (or programs, or shard counts), an incomplete shard, a shard given twice,
/// missing shards, a manifest whose items do not match its shard.
pub fn check(
    mut shards: Vec<(PathBuf, Manifest)>,
) -> Result<Vec<(PathBuf, Manifest)>, Vec<String>> {
    let mut errors = Vec::new();
    let Some((first_dir, first)) = shards.first().cloned() else {
        return Err(vec!["no shard folders given".to_owned()]);
    };
    let show = |p: &Path| p.display().to_string();
    for (dir, m) in &shards[1..] {
        let same = |what: &str, a: &dyn core::fmt::Display, b: &dyn core::fmt::Display| {
            format!(
                "{} and {} are not shards of one study: {what} {a} vs {b}",
                show(&first_dir),
                show(dir)
            )
        };
        if m.study != first.study {
            errors.push(same("study hash", &short(&first.study), &short(&m.study)));
        } else if m.program != first.program {
            errors.push(same("program", &first.program, &m.program));
        } else if m.shards != first.shards {
            errors.push(same("shard count", &first.shards, &m.shards));
        }
    }
    for (dir, m) in &shards {
        if !m.complete {
            errors.push(format!(
                "{}: shard {} is partial (some of its items failed or did not run); run it \
                 again",
                show(dir),
                m.shard()
            ));
        }
        let expected = m.shard().range(m.items);
        if m.shard == 0 || m.shard > m.shards || expected != (m.first..m.end) {
            errors.push(format!(
                "{}: {FILE_NAME} is inconsistent: shard {} of {} items should hold items \
                 {}..{}, it says {}..{}",
                show(dir),
                m.shard(),
                m.items,
                expected.start,
                expected.end,
                m.first,
                m.end
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    shards.sort_by_key(|(_, m)| m.shard);
    for pair in shards.windows(2) {
        if pair[0].1.shard == pair[1].1.shard {
            errors.push(format!(
                "{} and {} are both shard {}; give each shard once",
                show(&pair[0].0),
                show(&pair[1].0),
                pair[0].1.shard()
            ));
        }
    }
    let missing: Vec<String> = (1..=first.shards)
        .filter(|k| !shards.iter().any(|(_, m)| m.shard == *k))
        .map(|k| format!("{k}/{}", first.shards))
        .collect();
    if !missing.is_empty() {
        errors.push(format!(
            "missing shard{} {} of the study (given: {})",
            if missing.len() > 1 { "s" } else { "" },
            missing.join(", "),
            shards
                .iter()
                .map(|(d, m)| format!("{} in {}", m.shard(), show(d)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if errors.is_empty() {
        Ok(shards)
    } else {
        Err(errors)
    }
}

/// The first 12 hex digits of a hash, for messages.
fn short(hash: &str) -> &str {
    &hash[..hash.len().min(12)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifest(shard: usize, shards: usize) -> Manifest {
        let range = Shard {
            index: shard,
            count: shards,
        }
        .range(10);
        Manifest {
            program: "models 0.1.0".into(),
            study: study_hash("models 0.1.0", "study"),
            kind: "monte_carlo".into(),
            shard,
            shards,
            items: 10,
            first: range.start,
            end: range.end,
            complete: true,
            details: serde_yaml::Value::Null,
        }
    }

    fn set(ks: &[usize]) -> Vec<(PathBuf, Manifest)> {
        ks.iter()
            .map(|&k| (PathBuf::from(format!("s{k}")), manifest(k, 3)))
            .collect()
    }

    #[test]
    fn the_hash_is_sha256_of_program_and_study() {
        // `printf 'p\ns' | sha256sum`
        assert_eq!(
            study_hash("p", "s"),
            "4a24ad419990992bc33bf2193db76a0a2c9ffdf35e51967e76e2fec8f73f7b48"
        );
        assert_ne!(
            study_hash("models 0.1.0", "a"),
            study_hash("models 0.1.1", "a")
        );
    }

    #[test]
    fn a_complete_set_comes_back_in_shard_order() {
        let ok = check(set(&[3, 1, 2])).unwrap();
        let order: Vec<usize> = ok.iter().map(|(_, m)| m.shard).collect();
        assert_eq!(order, [1, 2, 3]);
    }

    #[test]
    fn refuses_gaps_duplicates_and_other_studies() {
        assert_eq!(
            check(set(&[1, 3])).unwrap_err(),
            ["missing shard 2/3 of the study (given: 1/3 in s1, 3/3 in s3)"]
        );
        let mut twice = set(&[1, 2, 3]);
        twice.push(("again".into(), manifest(2, 3)));
        assert_eq!(
            check(twice).unwrap_err(),
            ["s2 and again are both shard 2/3; give each shard once"]
        );
        let mut other = set(&[1, 2, 3]);
        other[2].1.study = study_hash("models 0.1.0", "another");
        let e = check(other).unwrap_err();
        assert_eq!(e.len(), 1);
        assert!(
            e[0].starts_with("s1 and s3 are not shards of one study: study hash "),
            "{e:?}"
        );
        let mut partial = set(&[1, 2, 3]);
        partial[1].1.complete = false;
        assert_eq!(
            check(partial).unwrap_err(),
            ["s2: shard 2/3 is partial (some of its items failed or did not run); run it again"]
        );
        let mut counts = set(&[1, 2]);
        counts[1].1 = manifest(2, 4);
        assert!(check(counts).unwrap_err()[0].contains("shard count 3 vs 4"));
    }

    #[test]
    fn the_manifest_round_trips_through_yaml() {
        let m = manifest(2, 3);
        let text = m.to_yaml();
        assert!(text.starts_with("# One shard of a study: items 3..6 (end excluded) of 10."));
        assert_eq!(serde_yaml::from_str::<Manifest>(&text).unwrap(), m);
    }
}
