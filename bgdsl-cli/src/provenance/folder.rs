//! The folder a run writes into when `--out` does not name one, so that runs with
//! different overrides do not overwrite each other's results:
//!
//! - `out/<name>` when the command line overrides nothing; `<name>` is the model's
//!   (`models run quick_return` and `cargo run --release` write `out/quick_return/`) or
//!   the scenario file's without its extension (`models run x.yaml` writes `out/x/`);
//! - `out/<name>-<overrides>` otherwise, the overrides written `key=value` and joined
//!   by commas: the `--set` parameters sorted by name, each with the value the run
//!   uses (a vector's numbers joined by `_`), then `solver`, `rtol`, `atol`, `step`,
//!   `t_start`, `t_end`, `interval` and `max_steps`
//!   when given: `models run quick_return --set w_drive=4 --set d=0.3` writes
//!   `out/quick_return-d=0.3,w_drive=4/`, and `--solver dopri5 --rtol 1e-8` adds
//!   `solver=dopri5,rtol=1e-8`;
//! - when that list is longer than [`MAX_SLUG`] characters or holds a character other
//!   than ASCII letters, digits and `._+-=,`, its first [`KEPT`] characters (each other
//!   character made `_`), `-`, and 8 hexadecimal digits of a hash of the whole list
//!   (FNV-1a), so that different overrides still get different folders.
//!
//! `--no-plots` does not count (it changes no number); `--out DIR` writes to `DIR`
//! exactly, whatever the overrides.

use std::collections::BTreeSet;
use std::path::PathBuf;

use serde_yaml::{Mapping, Value};

use crate::catalog::format_value;
use crate::scenario::Overrides;

/// The longest list of overrides written out whole in a folder name.
pub const MAX_SLUG: usize = 64;

/// How much of a list too long or not safe in a file name is kept before its hash.
pub const KEPT: usize = 40;

/// The command line's overrides that name the folder, as `(key, value)`, in the order
/// of the [module documentation](self). `params` are the run's parameters (so that
/// `--set m=2.0` and `--set m=2` name the same folder).
pub fn command_line_settings(overrides: &Overrides, params: &Mapping) -> Vec<(String, String)> {
    let names: BTreeSet<&str> = overrides
        .set
        .iter()
        .filter_map(|s| s.split_once('=').map(|(name, _)| name.trim()))
        .collect();
    let mut settings: Vec<(String, String)> = names
        .into_iter()
        .map(|name| {
            let value = params
                .get(name)
                .map(compact)
                .unwrap_or_else(|| "?".to_owned());
            (name.to_owned(), value)
        })
        .collect();
    if let Some(solver) = &overrides.solver {
        settings.push(("solver".to_owned(), solver.trim().to_owned()));
    }
    for (key, value) in [
        ("rtol", overrides.rtol),
        ("atol", overrides.atol),
        ("step", overrides.step),
        ("t_start", overrides.t_start),
        ("t_end", overrides.t_end),
        ("interval", overrides.interval),
    ] {
        if let Some(v) = value {
            settings.push((key.to_owned(), format_value(&Value::from(v))));
        }
    }
    if let Some(n) = overrides.max_steps {
        settings.push(("max_steps".to_owned(), n.to_string()));
    }
    settings
}

/// A parameter's value for a folder name: a number in its shortest exact form, a
/// vector's numbers joined by `_`.
fn compact(value: &Value) -> String {
    match value {
        Value::Sequence(items) => items.iter().map(compact).collect::<Vec<_>>().join("_"),
        other => format_value(other),
    }
}

/// `out/<name>` or `out/<name>-<overrides>` (see the [module documentation](self)).
pub fn default_out_dir(name: &str, settings: &[(String, String)]) -> PathBuf {
    let out = PathBuf::from("out");
    if settings.is_empty() {
        return out.join(name);
    }
    out.join(format!("{name}-{}", slug(settings)))
}

/// The overrides as they appear in a folder name.
fn slug(settings: &[(String, String)]) -> String {
    let whole = settings
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(",");
    let safe = |c: char| c.is_ascii_alphanumeric() || "._+-=,".contains(c);
    if whole.len() <= MAX_SLUG && whole.chars().all(safe) {
        return whole;
    }
    let kept: String = whole
        .chars()
        .take(KEPT)
        .map(|c| if safe(c) { c } else { '_' })
        .collect();
    let hash = fnv1a(whole.as_bytes());
    format!("{kept}-{:08x}", (hash ^ (hash >> 32)) as u32)
}

/// The 64-bit FNV-1a hash (Fowler, Noll and Vo; its published offset basis and prime):
/// stable across builds and platforms, unlike `std`'s hasher.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pairs(items: &[(&str, &str)]) -> Vec<(String, String)> {
        items
            .iter()
            .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
            .collect()
    }

    #[test]
    fn defaults_keep_the_plain_folder() {
        assert_eq!(
            default_out_dir("quick_return", &[]),
            PathBuf::from("out/quick_return")
        );
    }

    #[test]
    fn overrides_are_spelled_out_when_short_and_safe() {
        let dir = default_out_dir("quick_return", &pairs(&[("d", "0.3"), ("w_drive", "4")]));
        assert_eq!(dir, PathBuf::from("out/quick_return-d=0.3,w_drive=4"));
    }

    #[test]
    fn long_or_unsafe_overrides_are_cut_and_hashed() {
        let long: Vec<(String, String)> = (0..12)
            .map(|i| (format!("K{i:02}"), "100000".to_owned()))
            .collect();
        let name = slug(&long);
        assert_eq!(name.len(), KEPT + 9, "{name}");
        assert!(name.starts_with("K00=100000,K01=100000,"), "{name}");
        let mut other = long.clone();
        other[11].1 = "100001".to_owned();
        assert_ne!(
            slug(&other),
            name,
            "a difference past the cut changes the hash"
        );

        let odd = slug(&pairs(&[("solver", "radau5/../x")]));
        assert!(odd.starts_with("solver=radau5_.._x-"), "{odd}");
        assert!(!odd.contains('/'));
    }

    #[test]
    fn the_hash_is_fnv1a() {
        // Published test vectors of 64-bit FNV-1a.
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn settings_are_sorted_and_use_the_run_values() {
        let overrides = Overrides {
            set: vec!["w_drive=4.0".into(), "d = 0.3".into(), "w_drive=4".into()],
            solver: Some("dopri5".into()),
            rtol: Some(1e-8),
            t_end: Some(2.0),
            ..Overrides::default()
        };
        let mut params = Mapping::new();
        params.insert("w_drive".into(), Value::from(4.0));
        params.insert("d".into(), Value::from(0.3));
        params.insert(
            "l1".into(),
            Value::Sequence(vec![0.2.into(), 0.01.into(), 0.01.into()]),
        );
        assert_eq!(
            command_line_settings(&overrides, &params),
            pairs(&[
                ("d", "0.3"),
                ("w_drive", "4"),
                ("solver", "dopri5"),
                ("rtol", "1e-8"),
                ("t_end", "2")
            ])
        );
        let vector = Overrides {
            set: vec!["l1=[0.2,0.01,0.01]".into()],
            ..Overrides::default()
        };
        assert_eq!(
            command_line_settings(&vector, &params),
            pairs(&[("l1", "0.2_0.01_0.01")])
        );
    }
}
