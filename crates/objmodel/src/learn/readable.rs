//! Learning from the demonstrations that can be read ([`Learner::learn_readable`]): a batch
//! of files from a lab holds the odd one a logger broke, and the others still teach.

use super::{Learner, Source};
use crate::observation::Observation;
use crate::tree::Tree;
use crate::{Error, Result};
use std::path::Path;

/// A demonstration [`Learner::learn_readable`] left out: its index among the sources given,
/// and the error that names its file.
#[derive(Debug)]
pub struct LeftOut {
    /// Index among the sources given.
    pub index: usize,
    /// Why it could not be read (a file, a line and the problem).
    pub error: Error,
}

impl Source<'_> {
    /// Whether `file` is one this source reads (its object's or its palm's; a bag folder's
    /// files).
    pub fn reads(&self, file: &Path) -> bool {
        match *self {
            Source::Files { object, palm } => object == file || palm == Some(file),
            Source::Take { path, .. } => path == file,
            Source::Bag { path, .. } => file.starts_with(path),
            Source::Memory(_) => false,
        }
    }
}

impl Learner {
    /// [`Learner::learn_with_progress`] of the demonstrations that can be read: one whose file
    /// an error names ([`Error::file`]: a line that does not read, a file that cannot be
    /// opened) is left out, and the others are learnt without it (the noise and the centre of
    /// mass they share are then theirs alone). Each source is read once (`analysed` gets each
    /// index once, in order, whether it was read or left out); only an error in the stages
    /// after the reading (a file that changed under the learner) costs another pass over the
    /// others. Returns the reports of those learnt, in order, and those left out, in the
    /// order found. An error that names no source, or the last source's, is returned as
    /// [`Learner::learn`] returns it. `tree` changes only on success.
    pub fn learn_readable(
        &self,
        tree: &mut Tree,
        sources: &[Source],
        mut analysed: impl FnMut(usize),
    ) -> Result<(Vec<Observation>, Vec<LeftOut>)> {
        let (mut kept, mut per_source, mut left_out) = (Vec::new(), Vec::new(), Vec::new());
        for (k, source) in sources.iter().enumerate() {
            match self.observe_all(source) {
                Ok(o) => {
                    kept.push(k);
                    per_source.push(o);
                }
                Err(error) if names(&error, source) => left_out.push(LeftOut { index: k, error }),
                Err(error) => return Err(error),
            }
            analysed(k);
        }
        if kept.is_empty() {
            if let Some(last) = left_out.pop() {
                return Err(last.error);
            }
        }
        // The observations of the first pass; a pass after an error past the reading (a file
        // that changed under the learner) reads the others again.
        let mut observed = Some(per_source);
        loop {
            let mut attempt = tree.clone();
            let these: Vec<Source> = kept.iter().map(|&i| sources[i]).collect();
            let learnt = match observed.take() {
                Some(per_source) => self.fuse_observed(&mut attempt, &these, per_source),
                None => self.learn(&mut attempt, &these),
            };
            match learnt {
                Ok(reports) => {
                    *tree = attempt;
                    return Ok((reports, left_out));
                }
                Err(error) => leave_out(error, sources, &mut kept, &mut left_out)?,
            }
        }
    }
}

/// Whether `error` names a file that `source` reads.
fn names(error: &Error, source: &Source) -> bool {
    error.file().is_some_and(|f| source.reads(f))
}

/// Move the source among `kept` (indices into `sources`) whose file `error` names to
/// `left_out`; the error itself where it names none of them, or the last of them.
fn leave_out(
    error: Error,
    sources: &[Source],
    kept: &mut Vec<usize>,
    left_out: &mut Vec<LeftOut>,
) -> Result<()> {
    match kept.iter().position(|&i| names(&error, &sources[i])) {
        Some(k) if kept.len() > 1 => {
            left_out.push(LeftOut {
                index: kept.remove(k),
                error,
            });
            Ok(())
        }
        _ => Err(error),
    }
}
