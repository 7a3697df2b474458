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
    /// opened) is left out, and the others are learnt again without it (the noise and the
    /// centre of mass they share are then theirs alone). `analysed` gets indices among
    /// `sources`. Returns the reports of those learnt, in order, and those left out, in the
    /// order found. An error that names no source, or the last source's, is returned as
    /// [`Learner::learn`] returns it. `tree` changes only on success. Each source left out
    /// costs one more pass over the others.
    pub fn learn_readable(
        &self,
        tree: &mut Tree,
        sources: &[Source],
        mut analysed: impl FnMut(usize),
    ) -> Result<(Vec<Observation>, Vec<LeftOut>)> {
        let mut kept: Vec<usize> = (0..sources.len()).collect();
        let mut left_out = Vec::new();
        loop {
            let mut attempt = tree.clone();
            let these: Vec<Source> = kept.iter().map(|&i| sources[i]).collect();
            let error = match self.learn_with_progress(&mut attempt, &these, |k| analysed(kept[k]))
            {
                Ok(reports) => {
                    *tree = attempt;
                    return Ok((reports, left_out));
                }
                Err(e) => e,
            };
            let named = error
                .file()
                .and_then(|f| kept.iter().position(|&i| sources[i].reads(f)));
            match named {
                Some(k) if kept.len() > 1 => left_out.push(LeftOut {
                    index: kept.remove(k),
                    error,
                }),
                _ => return Err(error),
            }
        }
    }
}
