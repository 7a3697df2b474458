//! Classifying demonstrations straight from their files, streaming.

use super::{Analyzer, Classification, Config};
use crate::format;
use crate::Result;
use std::path::Path;

/// Classify the demonstration in `object` (TUM or CSV), with `palm` as its palm trajectory
/// when instrumented. Both files are streamed in time order: memory does not grow with their
/// length. The demonstration's name is the object file's name.
pub fn classify_files(object: &Path, palm: Option<&Path>, config: &Config) -> Result<Classification> {
    let name = object.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| object.display().to_string());
    let mut a = Analyzer::new(&name, config, palm.is_some());
    let mut objects = format::open(object)?;
    match palm {
        None => {
            for p in objects {
                a.push_object(&p?);
            }
        }
        Some(palm) => {
            let mut palms = format::open(palm)?;
            let (mut o, mut p) = (objects.next().transpose()?, palms.next().transpose()?);
            loop {
                match (&o, &p) {
                    (None, None) => break,
                    (Some(x), Some(y)) if y.t <= x.t => {
                        a.push_palm(y);
                        p = palms.next().transpose()?;
                    }
                    (Some(x), _) => {
                        a.push_object(x);
                        o = objects.next().transpose()?;
                    }
                    (None, Some(y)) => {
                        a.push_palm(y);
                        p = palms.next().transpose()?;
                    }
                }
            }
        }
    }
    a.finish().map_err(|e| match e {
        crate::Error::Data(msg) => crate::Error::File { file: object.to_path_buf(), msg },
        e => e,
    })
}
