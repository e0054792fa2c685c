//! `merge`: shard folders checked and joined into the one-process result.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::super::folder::RunFolder;
use super::super::run::{settle_drawing, Observer};
use super::super::RunError;
use super::files::{read_shard, write_study};
use super::{StudyOutcome, StudyShape};
use crate::provenance::{self, RunRecord};
use crate::study::manifest::{self, Manifest};

/// Joins the shard folders `dirs` of a study or a sweep (`run ... --shard K/N`) into
/// the one-process result at `out`, as one results set: the data files bit for bit as
/// the run without shards writes them, the figures and `index.html` drawn again, and
/// `run.yaml`. Nothing is written when the shards do not make one whole study.
///
/// # Errors
///
/// The outer `Err`: every problem with the set (other studies, duplicates, gaps,
/// partial shards, unreadable or edited files, `out` being one of `dirs`), one message
/// each, naming the folders; nothing was written. The inner `Err`: the joined set
/// could not be written ([`RunError`]).
pub fn merge(
    dirs: &[PathBuf],
    out: &Path,
    observer: &dyn Observer,
) -> Result<Result<StudyOutcome, RunError>, Vec<String>> {
    let mut manifests = Vec::new();
    let mut errors = Vec::new();
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if let Some(dir) = dirs.iter().find(|d| same(d, out)) {
        return Err(vec![format!(
            "the output folder {} is one of the shards: the merge would replace it; choose \
             another --out",
            dir.display()
        )]);
    }
    for dir in dirs {
        match Manifest::read(dir) {
            Ok(m) => manifests.push((dir.clone(), m)),
            Err(e) => errors.push(e),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let shards = manifest::check(manifests)?;
    let kind = shards[0].1.kind.clone();
    match kind.as_str() {
        "monte_carlo" => merge_study(&shards, out, observer),
        "sweep" => super::super::sweep::merge_sweep(&shards, out, observer),
        other => Err(vec![format!(
            "{}: unknown kind of study `{other}`",
            shards[0].0.display()
        )]),
    }
}

fn merge_study(
    shards: &[(PathBuf, Manifest)],
    out: &Path,
    observer: &dyn Observer,
) -> Result<Result<StudyOutcome, RunError>, Vec<String>> {
    let shape: StudyShape = serde_yaml::from_value(shards[0].1.details.clone()).map_err(|e| {
        vec![format!(
            "{}: {}: {e}",
            shards[0].0.display(),
            manifest::FILE_NAME
        )]
    })?;
    let mut times: Option<Vec<f64>> = None;
    let mut rows = Vec::new();
    for (dir, m) in shards {
        let (t, r) = read_shard(dir, &shape, m).map_err(|e| vec![e])?;
        if times.as_ref().is_some_and(|times| *times != t) {
            return Err(vec![format!(
                "{}: its sample times differ from the first shard's",
                dir.display()
            )]);
        }
        times = Some(t);
        rows.extend(r);
    }
    let times = times.unwrap_or_default();
    let started = Instant::now();
    let result = (|| {
        let folder = RunFolder::begin(out)?;
        let head = format!(
            "monte carlo    {}: {} samples merged from {} shards\n",
            shape.model,
            rows.len(),
            shards.len()
        );
        let (mut files, drawn, text) =
            write_study(folder.path(), &shape, &times, &rows, &head, observer)?;
        let mut failure = None;
        let (_, figures_error) = settle_drawing(drawn, &mut failure, observer)?;
        if let Some(path) = merged_record(shards, folder.path(), &files)? {
            files.push(path);
        }
        let target = folder.commit(failure.is_some())?;
        Ok(StudyOutcome {
            summary: format!("{text}results        {}\n", target.display()),
            files: files.iter().map(|f| target.join(f)).collect(),
            failure,
            figures_error,
            wall: started.elapsed(),
        })
    })();
    Ok(result)
}

/// Writes the record of a merge into `dir`: the first shard's `run.yaml` (the study's
/// settings are the same in every shard) without its shard, with the merge's command
/// line, the folders joined and the files written. `None` when the shard has no record.
pub(in crate::catalog) fn merged_record(
    shards: &[(PathBuf, Manifest)],
    dir: &Path,
    files: &[String],
) -> Result<Option<String>, RunError> {
    let Ok(text) = std::fs::read_to_string(shards[0].0.join(provenance::FILE_NAME)) else {
        return Ok(None);
    };
    let Ok(mut record) = serde_yaml::from_str::<RunRecord>(&text) else {
        return Ok(None);
    };
    record.shard = None;
    record.command_line = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    record.merged_from = shards
        .iter()
        .map(|(d, _)| d.display().to_string())
        .collect();
    record.results = files
        .iter()
        .filter(|f| f.ends_with(".csv"))
        .cloned()
        .collect();
    provenance::write(dir, &record)?;
    Ok(Some(provenance::FILE_NAME.to_owned()))
}
