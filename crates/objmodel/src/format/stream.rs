//! Lines out of a `BufRead`: complete lines are read straight out of its buffer (the common
//! TUM lines by the fast path, [`FastLines`]), a line that straddles two buffer fills is
//! carried over, and a line longer than [`MAX_LINE`] is an error, however it lies in the
//! buffer (carried or whole: so the error does not depend on the size of the buffer, or on
//! whether the file is read, mapped or in memory).

use super::fast_run::FastLines;
use super::layout::MAX_LINE;
use super::line::{Mode, State};
use super::tum::scan_tum;
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use memchr::memchr;
use std::io::BufRead;

/// The byte side of a reader: the part of a line carried over from the last buffer fill, and
/// the fast line scanners.
#[derive(Default)]
pub(crate) struct Stream {
    /// Part of a line that straddles two buffer fills.
    carry: Vec<u8>,
    /// The current line is longer than `MAX_LINE`: drop bytes until its end.
    overlong: bool,
    /// The fast line scanners.
    pub(crate) fast: FastLines,
}

impl Stream {
    /// Read on: decode the complete lines already in the read buffer straight into `out` (at
    /// most `limit` poses; lines into `lines`), or else read one line the slow way and return
    /// its item. Returns `None` when poses were pushed (an error after them goes to `pending`)
    /// or at the end. Never waits for more input once a pose is decoded, so a live stream on
    /// stdin is not delayed.
    pub(crate) fn step<R: BufRead>(
        &mut self,
        reader: &mut R,
        st: &mut State,
        pending: &mut Option<Error>,
        out: &mut Vec<StampedPose>,
        mut lines: Option<&mut Vec<usize>>,
        limit: usize,
    ) -> Option<Result<StampedPose>> {
        while !st.done {
            let buf = match reader.fill_buf() {
                Ok(b) => b,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(source) => {
                    st.done = true;
                    return Some(Err(Error::Io {
                        file: st.file.clone(),
                        source,
                    }));
                }
            };
            if buf.is_empty() {
                // End of input: a last line without '\n'.
                st.done = true;
                if self.carry.is_empty() && !self.overlong {
                    return None;
                }
                return self.take_last(st);
            }
            let whole_lines = self.carry.is_empty() && !self.overlong;
            if whole_lines && st.track.line_no > 0 {
                // Fast path: complete lines straight from the buffer.
                let mut off = 0;
                let mut err = None;
                let mut pushed = 0;
                while pushed < limit {
                    let rest = &buf[off..];
                    let (r, len) = if let Mode::Tum = st.mode {
                        let lines = lines.as_deref_mut();
                        let (used, n) =
                            self.fast
                                .decode(&mut st.track, rest, out, lines, limit - pushed);
                        if n > 0 {
                            st.pose_line = st.track.prev_line;
                            st.last_pose = out.last().copied();
                        }
                        off += used;
                        pushed += n;
                        if pushed == limit {
                            break;
                        }
                        let rest = &buf[off..];
                        let scan = scan_tum(rest);
                        if scan.end == rest.len() {
                            break; // incomplete line
                        }
                        if scan.end > MAX_LINE {
                            (st.too_long(), scan.end)
                        } else {
                            st.track.line_no += 1;
                            (st.finish_tum(&scan, &rest[..scan.end]), scan.end)
                        }
                    } else {
                        let Some(e) = memchr(b'\n', rest) else { break };
                        if e > MAX_LINE {
                            (st.too_long(), e)
                        } else {
                            (st.handle(&rest[..e]), e)
                        }
                    };
                    off += len + 1;
                    match r {
                        Some(Ok(p)) => {
                            out.push(p);
                            pushed += 1;
                            if let Some(l) = lines.as_deref_mut() {
                                l.push(st.track.line_no);
                            }
                        }
                        Some(Err(e)) => {
                            err = Some(e);
                            break;
                        }
                        None => {}
                    }
                }
                if off > 0 {
                    reader.consume(off);
                    if let Some(e) = err {
                        if pushed == 0 {
                            return Some(Err(e));
                        }
                        *pending = Some(e);
                    }
                    if pushed > 0 {
                        return None;
                    }
                    continue;
                }
            }
            // Slow path: the first line, or a line that straddles two buffer fills.
            let newline = memchr(b'\n', buf);
            if let (Some(i), true) = (newline, whole_lines) {
                let r = if i > MAX_LINE {
                    st.too_long()
                } else {
                    st.handle(&buf[..i])
                };
                reader.consume(i + 1);
                if r.is_some() {
                    return r;
                }
                continue;
            }
            let take = newline.unwrap_or(buf.len());
            if !self.overlong {
                if self.carry.len() + take > MAX_LINE {
                    self.overlong = true;
                    self.carry = Vec::new();
                } else {
                    self.carry.extend_from_slice(&buf[..take]);
                }
            }
            match newline {
                Some(i) => {
                    reader.consume(i + 1);
                    if let Some(r) = self.take_carry(st) {
                        return Some(r);
                    }
                }
                None => reader.consume(take),
            }
        }
        None
    }

    /// Handle the file's last line, which has no `\n` (carried, or over-long): after poses, one
    /// that does not read as a pose is a line a logger stopped writing in the middle of, left
    /// out and said (`skipped.rs`), not an error.
    fn take_last(&mut self, st: &mut State) -> Option<Result<StampedPose>> {
        let after_poses = st.track.prev_line > 0;
        match self.take_carry(st) {
            Some(Err(Error::Parse { line, msg, .. })) if after_poses => {
                st.cut_short(line, msg);
                None
            }
            r => r,
        }
    }

    /// Handle the carried (or over-long) line and reset the carry buffer.
    fn take_carry(&mut self, st: &mut State) -> Option<Result<StampedPose>> {
        if std::mem::take(&mut self.overlong) {
            return st.too_long();
        }
        let line = std::mem::take(&mut self.carry);
        let r = st.handle(&line);
        self.carry = line;
        self.carry.clear();
        r
    }
}
