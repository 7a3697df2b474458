//! Classifying demonstrations straight from their files, streaming.

use super::{Analyzer, Classification, Config, RotatingCleaner};
use crate::clean::RawFrame;
use crate::fast::avx2_or_baseline;
use crate::format;
use crate::recording::Recorder;
use crate::trajectory::StampedPose;
use crate::Result;
use nalgebra::{UnitQuaternion, Vector3};
use std::path::Path;

/// A stage of the analysis that can run on the parsing thread: it takes poses and emits
/// items for the rest of the analysis on the calling thread.
trait Front: Send + 'static {
    /// What it emits.
    type Out: Copy + Send + 'static;
    /// Push the next pose.
    fn push_pose(&mut self, p: &StampedPose, out: &mut impl FnMut(Self::Out));
    /// Flush at the end of the stream.
    fn finish_poses(self, out: &mut impl FnMut(Self::Out));
}

/// A cleaned frame as the parsing thread hands it over, in 88 bytes (every byte crosses
/// between the cores' caches): time \[s\], orientation, position \[m\] and accumulated
/// rotation \[rad\], NaN for a frame rejected as an outlier. The frame's index is its place
/// in the stream, counted by the receiver.
#[derive(Clone, Copy)]
struct Handed {
    t: f64,
    q: UnitQuaternion<f64>,
    p: Vector3<f64>,
    rot: Vector3<f64>,
}

impl Front for RotatingCleaner {
    type Out = Handed;
    #[inline(always)]
    fn push_pose(&mut self, p: &StampedPose, out: &mut impl FnMut(Handed)) {
        self.push(p, &mut |f, o, r| out(handed(&f, o, r)))
    }
    fn finish_poses(self, out: &mut impl FnMut(Handed)) {
        self.finish(&mut |f, o, r| out(handed(&f, o, r)))
    }
}

#[inline(always)]
fn handed(f: &RawFrame, outlier: bool, rot: Vector3<f64>) -> Handed {
    Handed {
        t: f.t,
        q: f.q,
        p: f.p,
        rot: if outlier {
            Vector3::repeat(f64::NAN)
        } else {
            rot
        },
    }
}

/// Classify the demonstration in `object` (TUM or CSV), with `palm` as its palm trajectory
/// when instrumented. Both files are streamed in time order: memory does not grow with their
/// length. The demonstration's name is the object file's name.
pub fn classify_files(
    object: &Path,
    palm: Option<&Path>,
    config: &Config,
) -> Result<Classification> {
    classify_files_recording(object, palm, config, None)
}

/// [`classify_files`], handing every frame to `recorder` as well (for the dynamics, in the
/// same pass over the files).
pub(crate) fn classify_files_recording(
    object: &Path,
    palm: Option<&Path>,
    config: &Config,
    mut recorder: Option<&mut Recorder>,
) -> Result<Classification> {
    let name = object
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| object.display().to_string());
    let mut a = Analyzer::new(&name, config, palm.is_some());
    match palm {
        None => {
            // Robust: parsing, cleaning and the accumulated rotation on the background
            // thread; rest detection, segments and blocks on this one. Measured on 10^6 poses
            // (CPU per thread, medians of interleaved runs): the parsing thread ~57 ms, this
            // one ~57-59 ms, the mapping helper ~5 ms; with the rotation here instead, the
            // wall time did not improve; with the whole rest detection there (`ObjectFront`),
            // that thread is much the busier.
            if let Some(cleaner) = a.take_object_cleaner() {
                let front = RotatingCleaner::new(cleaner);
                let mut index = 0;
                CleanedFrames::spawn(format::open(object)?, front).for_each_chunk(|chunk| {
                    if let Some(r) = recorder.as_deref_mut() {
                        let (first, end) = (index as u64, (index + chunk.len()) as u64);
                        let mut i = r.next_object_index(first);
                        while i < end {
                            let h = &chunk[(i - first) as usize];
                            r.object(i, h.t, &h.q);
                            i = r.next_object_index(i + 1);
                        }
                    }
                    push_handed(&mut a, chunk, &mut index)
                })?;
            } else {
                for (i, p) in (0u64..).zip(ThreadedPoses::spawn(format::open(object)?)) {
                    let p = p?;
                    if let Some(r) = recorder.as_deref_mut() {
                        r.object(i, p.t, &p.pose.rotation);
                    }
                    a.push_object(&p);
                }
            }
        }
        Some(palm) => {
            let mut objects = ThreadedPoses::spawn(format::open(object)?);
            let mut palms = ThreadedPoses::spawn(format::open(palm)?);
            let (mut o, mut p) = (objects.next().transpose()?, palms.next().transpose()?);
            let mut index = 0u64;
            loop {
                let palm_first = match (&o, &p) {
                    (None, None) => break,
                    (Some(x), Some(y)) => y.t <= x.t,
                    (Some(_), None) => false,
                    (None, Some(_)) => true,
                };
                if palm_first {
                    let y = p.as_ref().expect("a palm pose");
                    if let Some(r) = recorder.as_deref_mut() {
                        r.palm(y);
                    }
                    a.push_palm(y);
                    p = palms.next().transpose()?;
                } else {
                    let x = o.as_ref().expect("an object pose");
                    if let Some(r) = recorder.as_deref_mut() {
                        r.object(index, x.t, &x.pose.rotation);
                    }
                    index += 1;
                    a.push_object(x);
                    o = objects.next().transpose()?;
                }
            }
        }
    }
    a.finish().map_err(|e| match e {
        crate::Error::Data(msg) => crate::Error::File {
            file: object.to_path_buf(),
            msg,
        },
        e => e,
    })
}

/// Poses parsed on a background thread, handed over in chunks through a bounded channel:
/// parsing (the largest single cost) overlaps the analysis, and memory stays bounded
/// (at most `CHANNEL_CHUNKS` chunks of `CHUNK_POSES` poses in flight). A chunk carries the
/// poses before the first error, then that error.
struct ThreadedPoses {
    rx: std::sync::mpsc::Receiver<(Vec<StampedPose>, Option<crate::Error>)>,
    /// Emptied chunks go back to the producer for reuse (see [`CleanedFrames`]).
    recycle: std::sync::mpsc::Sender<Vec<StampedPose>>,
    chunk: Vec<StampedPose>,
    pos: usize,
    error: Option<crate::Error>,
}

/// Poses per chunk handed from the parsing thread (512 KiB of poses): large enough that the
/// hand-over is rare (chunks of 1024 cost more thread switches and gained nothing, measured).
const CHUNK_POSES: usize = 8192;
/// Items in the first chunk a [`CleanedFrames`] hands over: fewer, so that the receiving
/// thread starts after about 20 µs of parsing instead of 0.6 ms.
const FIRST_CHUNK_POSES: usize = 256;
/// Chunks in flight between the threads.
const CHANNEL_CHUNKS: usize = 4;
/// Poses decoded at a time on the parsing thread before they are cleaned (small enough to stay
/// in the first-level cache: 16 KiB).
const PARSE_BATCH: usize = 256;

impl ThreadedPoses {
    fn spawn<R: std::io::BufRead + Send + 'static>(mut poses: format::PoseReader<R>) -> Self {
        let (tx, rx) = std::sync::mpsc::sync_channel(CHANNEL_CHUNKS);
        let (recycle, recycled) = std::sync::mpsc::channel::<Vec<StampedPose>>();
        std::thread::spawn(move || loop {
            let mut chunk = recycled
                .try_recv()
                .unwrap_or_else(|_| Vec::with_capacity(CHUNK_POSES));
            let (more, error) = match poses.read_chunk(&mut chunk, CHUNK_POSES) {
                Ok(more) => (more, None),
                Err(e) => (false, Some(e)),
            };
            if (chunk.is_empty() && error.is_none()) || tx.send((chunk, error)).is_err() || !more {
                break;
            }
        });
        Self {
            rx,
            recycle,
            chunk: Vec::new(),
            pos: 0,
            error: None,
        }
    }
}

impl Iterator for ThreadedPoses {
    type Item = Result<StampedPose>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            if let Some(p) = self.chunk.get(self.pos) {
                self.pos += 1;
                return Some(Ok(*p));
            }
            if let Some(e) = self.error.take() {
                return Some(Err(e));
            }
            let (chunk, error) = self.rx.recv().ok()?;
            let mut done = std::mem::replace(&mut self.chunk, chunk);
            done.clear();
            let _ = self.recycle.send(done);
            self.pos = 0;
            self.error = error;
        }
    }
}

/// Poses parsed and put through a [`Front`] stage (the tag-flip cleaner and the accumulated
/// rotation) on a background thread, its output handed over in bounded chunks: on 2 cores this
/// balances the two threads best (see [`classify_files`]).
struct CleanedFrames<T> {
    rx: std::sync::mpsc::Receiver<(Vec<T>, Option<crate::Error>)>,
    /// Emptied chunks go back to the producer for reuse (fresh ones would cost page faults).
    recycle: std::sync::mpsc::Sender<Vec<T>>,
}

impl<T: Copy + Send + 'static> CleanedFrames<T> {
    fn spawn<R: std::io::BufRead + Send + 'static, F: Front<Out = T>>(
        mut poses: format::PoseReader<R>,
        mut cleaner: F,
    ) -> Self {
        let (tx, rx) = std::sync::mpsc::sync_channel(CHANNEL_CHUNKS);
        let (recycle, recycled) = std::sync::mpsc::channel::<Vec<T>>();
        std::thread::spawn(move || {
            let fresh = || {
                recycled
                    .try_recv()
                    .unwrap_or_else(|_| Vec::with_capacity(CHUNK_POSES))
            };
            let mut chunk = fresh();
            // The first chunk is handed over early, so that the receiver starts sooner.
            let mut chunk_len = FIRST_CHUNK_POSES;
            // Poses are decoded a batch at a time, then cleaned.
            let mut batch = Vec::with_capacity(PARSE_BATCH);
            loop {
                batch.clear();
                let (more, error) = match poses.read_chunk(&mut batch, PARSE_BATCH) {
                    Ok(more) => (more, None),
                    Err(e) => (false, Some(e)),
                };
                push_batch(&mut cleaner, &batch, &mut chunk);
                if let Some(e) = error {
                    let _ = tx.send((std::mem::take(&mut chunk), Some(e)));
                    return;
                }
                if !more {
                    break;
                }
                if chunk.len() >= chunk_len {
                    chunk_len = CHUNK_POSES;
                    if tx
                        .send((std::mem::replace(&mut chunk, fresh()), None))
                        .is_err()
                    {
                        return;
                    }
                }
            }
            cleaner.finish_poses(&mut |j| chunk.push(j));
            let _ = tx.send((chunk, None));
        });
        Self { rx, recycle }
    }
}

/// Put a batch of poses through `front`, its output appended to `chunk`: the whole stage
/// inlined into one loop, compiled for AVX2 where the processor has it (the same bits: no
/// multiply and add are fused). Parsing thread CPU on 10^6 poses, 12 interleaved runs each,
/// least: 68.0 ms with the stage called per pose in baseline code, 68.3 ms inlined in baseline
/// code, 60.0 ms inlined in AVX2 code (the 88-byte hand-over stores and the quaternion
/// arithmetic take 256-bit registers; `examples/clean_bench`, which keeps its own items, sees
/// only 1 ns/pose of it).
#[inline(always)]
fn push_batch<F: Front>(front: &mut F, batch: &[StampedPose], chunk: &mut Vec<F::Out>) {
    avx2_or_baseline!(push_batch_with(front, batch, chunk))
}

#[inline(always)]
fn push_batch_with<F: Front>(front: &mut F, batch: &[StampedPose], chunk: &mut Vec<F::Out>) {
    for p in batch {
        front.push_pose(p, &mut |j| chunk.push(j));
    }
}

/// Pass a hand-over chunk to the analysis, `index` being the number of the first frame in it
/// (advanced past the chunk): in AVX2 code where the processor has it, as [`push_batch`]
/// (the choice of code in the rest front end then folds away).
#[inline(always)]
fn push_handed(a: &mut Analyzer, chunk: &[Handed], index: &mut usize) {
    avx2_or_baseline!(push_handed_with(a, chunk, index))
}

#[inline(always)]
fn push_handed_with(a: &mut Analyzer, chunk: &[Handed], index: &mut usize) {
    for h in chunk {
        // Read in place, in the hand-over chunk (see `ItemRef`).
        let frame = (!h.rot.x.is_nan()).then_some((&h.q, &h.p, &h.rot));
        a.push_cleaned_rotated(*index, h.t, frame);
        *index += 1;
    }
}

impl<T> CleanedFrames<T> {
    /// Pass every hand-over chunk to `f` in order; an error from the parsing thread ends the
    /// stream and is returned.
    fn for_each_chunk(self, mut f: impl FnMut(&[T])) -> Result<()> {
        // While the first chunk is being parsed, give the parsing thread chunks whose pages
        // are already in place: the first touch of a page costs a fault, and on the parsing
        // thread it delays the stream. Three of the ~six chunks the stream fills: all of them
        // made this thread the slower one (in-process wall medians, 16 and 24 interleaved
        // runs: 68.0 -> 67.4 and 65.4 -> 63.6 ms with three instead of five).
        for _ in 0..CHANNEL_CHUNKS - 1 {
            let mut chunk: Vec<T> = Vec::with_capacity(CHUNK_POSES);
            let spare = chunk.spare_capacity_mut();
            let bytes = std::mem::size_of_val(spare);
            let base = spare.as_mut_ptr().cast::<u8>();
            for at in (0..bytes).step_by(4096) {
                // SAFETY: `at` is inside the spare capacity (uninitialised memory this vector
                // owns); writing a byte there initialises nothing the vector reads.
                unsafe { base.add(at).write_volatile(0) };
            }
            if self.recycle.send(chunk).is_err() {
                break;
            }
        }
        while let Ok((mut chunk, error)) = self.rx.recv() {
            f(&chunk);
            if let Some(e) = error {
                return Err(e);
            }
            chunk.clear();
            let _ = self.recycle.send(chunk);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{self, SynthBox, SynthDemo, SynthNoise, ToppleParams};
    use rand::{rngs::StdRng, SeedableRng};

    /// Takes the baseline code while it lives.
    struct BaselineOnly;

    impl BaselineOnly {
        fn new() -> Self {
            crate::fast::set_baseline_only(true);
            Self
        }
    }

    impl Drop for BaselineOnly {
        fn drop(&mut self) {
            crate::fast::set_baseline_only(false);
        }
    }

    /// Every kernel that chooses AVX2 code at run time gives the same classification, bit for
    /// bit, in its baseline code (the claim of `crate::lanes`): files of a topple, an
    /// instrumented topple, a quasi-static topple (the slow-motion path), a slide and a general
    /// motion, at real tracking noise, each classified from its files both ways. (On a
    /// processor without AVX2 both ways are the baseline code.)
    #[test]
    fn baseline_and_avx2_code_classify_alike() {
        let dir = std::env::temp_dir().join(format!("objmodel-isa-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let noise = SynthNoise::REAL;
        let mut rng = StdRng::seed_from_u64(77);
        let b = SynthBox::random(&mut rng);
        let topple = |push_s: f64, seed: u64| {
            let p = ToppleParams {
                side: (seed % 4) as usize,
                push_s,
                ..Default::default()
            };
            synth::topple(&b, &p, &noise, 30.0, seed)
        };
        let demos: Vec<(&str, SynthDemo)> = vec![
            ("topple", topple(1.5, 1)),
            (
                "instrumented",
                synth::instrumented_topple(&b, 2, 0.2, &noise, 30.0, 2),
            ),
            ("quasi_static", topple(60.0, 3)),
            ("slide", synth::slide(&b, &noise, 30.0, 4)),
            ("general", synth::general(&b, &noise, 30.0, 5)),
        ];
        let config = Config::default();
        for (name, d) in &demos {
            let object = dir.join(format!("{name}.tum"));
            format::write_tum(&object, &d.demo.object, name).unwrap();
            let palm = d.demo.palm.as_ref().map(|p| {
                let path = dir.join(format!("{name}.palm.tum"));
                format::write_tum(&path, p, name).unwrap();
                path
            });
            let fast = classify_files(&object, palm.as_deref(), &config).unwrap();
            let base = {
                let _baseline = BaselineOnly::new();
                classify_files(&object, palm.as_deref(), &config).unwrap()
            };
            assert_eq!(fast.kind, d.truth.kind, "{name}");
            assert_eq!(format!("{fast:?}"), format!("{base:?}"), "{name}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
