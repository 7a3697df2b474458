//! The parsing thread and the hand-over: a file's poses are parsed (and, for the robust method
//! without a palm, cleaned and their rotation accumulated) on a background thread and handed
//! over in bounded chunks to the thread that runs the rest of the analysis. Only for speed: the
//! results are those of pushing the poses one by one into an [`Analyzer`].

use super::avx2_or_baseline;
use crate::classify::cleaning::RotatingCleaner;
use crate::classify::Analyzer;
use crate::clean::RawFrame;
use crate::format;
use crate::trajectory::StampedPose;
use crate::Result;
use nalgebra::{UnitQuaternion, Vector3};

/// A stage of the analysis that can run on the parsing thread: it takes poses and emits
/// items for the rest of the analysis on the calling thread.
pub trait ParsingThreadWork: Send + 'static {
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
pub struct CleanedFrame {
    /// Time \[s\].
    pub t: f64,
    /// Orientation.
    pub q: UnitQuaternion<f64>,
    /// Position \[m\].
    pub p: Vector3<f64>,
    /// Accumulated rotation \[rad\], NaN for an outlier.
    pub rot: Vector3<f64>,
}

impl ParsingThreadWork for RotatingCleaner {
    type Out = CleanedFrame;
    #[inline(always)]
    fn push_pose(&mut self, p: &StampedPose, out: &mut impl FnMut(CleanedFrame)) {
        self.push(p, &mut |f, o, r| out(cleaned_frame(&f, o, r)))
    }
    fn finish_poses(self, out: &mut impl FnMut(CleanedFrame)) {
        self.finish(&mut |f, o, r| out(cleaned_frame(&f, o, r)))
    }
}

#[inline(always)]
fn cleaned_frame(f: &RawFrame, outlier: bool, rot: Vector3<f64>) -> CleanedFrame {
    CleanedFrame {
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

/// Poses parsed on a background thread, handed over in chunks through a bounded channel:
/// parsing (the largest single cost) overlaps the analysis, and memory stays bounded
/// (at most `CHANNEL_CHUNKS` chunks of `CHUNK_POSES` poses in flight). A chunk carries the
/// poses before the first error, then that error.
pub struct ThreadedPoses {
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
    pub fn spawn<R: std::io::BufRead + Send + 'static>(mut poses: format::PoseReader<R>) -> Self {
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

/// Poses parsed and put through a [`ParsingThreadWork`] stage (the tag-flip cleaner and the accumulated
/// rotation) on a background thread, its output handed over in bounded chunks: on 2 cores this
/// balances the two threads best (see `crate::classify::classify_files`).
pub struct CleanedFrames<T> {
    rx: std::sync::mpsc::Receiver<(Vec<T>, Option<crate::Error>)>,
    /// Emptied chunks go back to the producer for reuse (fresh ones would cost page faults).
    recycle: std::sync::mpsc::Sender<Vec<T>>,
}

impl<T: Copy + Send + 'static> CleanedFrames<T> {
    pub fn spawn<R: std::io::BufRead + Send + 'static, F: ParsingThreadWork<Out = T>>(
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
fn push_batch<F: ParsingThreadWork>(front: &mut F, batch: &[StampedPose], chunk: &mut Vec<F::Out>) {
    avx2_or_baseline!(#[inline(never)] fn<F: ParsingThreadWork>(
        front: &mut F = front,
        batch: &[StampedPose] = batch,
        chunk: &mut Vec<F::Out> = chunk,
    ) {
        push_batch_with(front, batch, chunk)
    })
}

#[inline(always)]
fn push_batch_with<F: ParsingThreadWork>(
    front: &mut F,
    batch: &[StampedPose],
    chunk: &mut Vec<F::Out>,
) {
    for p in batch {
        front.push_pose(p, &mut |j| chunk.push(j));
    }
}

/// Frames between two prefetches of the hand-over chunk, and how far ahead
/// ([`super::prefetch`]).
const PREFETCH_EVERY: usize = 8;
const PREFETCH_FRAMES_AHEAD: usize = 32;

/// Pass a hand-over chunk to the analysis, `index` being the number of the first frame in it
/// (advanced past the chunk): in AVX2 code where the processor has it, as [`push_batch`]
/// (the choice of code in the rest front end then folds away).
#[inline(always)]
pub fn push_cleaned_frames(a: &mut Analyzer, chunk: &[CleanedFrame], index: &mut usize) {
    avx2_or_baseline!(#[inline(never)] fn(
        a: &mut Analyzer = a,
        chunk: &[CleanedFrame] = chunk,
        index: &mut usize = index,
    ) {
        push_cleaned_frames_with(a, chunk, index)
    })
}

#[inline(always)]
fn push_cleaned_frames_with(a: &mut Analyzer, chunk: &[CleanedFrame], index: &mut usize) {
    for (k, h) in chunk.iter().enumerate() {
        // The parsing thread wrote these frames on the other core: fetched ahead.
        if k % PREFETCH_EVERY == 0 {
            super::prefetch(
                chunk
                    .as_ptr()
                    .wrapping_add(k + PREFETCH_FRAMES_AHEAD)
                    .cast(),
                PREFETCH_EVERY * std::mem::size_of::<CleanedFrame>(),
            );
        }
        // Read in place, in the hand-over chunk (see `SampleRef`).
        let frame = (!h.rot.x.is_nan()).then_some((&h.q, &h.p, &h.rot));
        a.push_cleaned_rotated(*index, h.t, frame);
        *index += 1;
    }
}

impl<T> CleanedFrames<T> {
    /// Pass every hand-over chunk to `f` in order; an error from the parsing thread ends the
    /// stream and is returned.
    pub fn for_each_chunk(self, mut f: impl FnMut(&[T])) -> Result<()> {
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
