//! Reading a large regular file through memory-mapped windows instead of `read` calls.
//!
//! `read` copies every byte from the kernel's page cache into the reader's buffer; for a
//! 100 MB pose file that copy was about a fifth of the parsing thread's time. Mapping the file
//! lets the parser read the page cache directly. The file is mapped one [`WINDOW`] at a time
//! and each window is unmapped once it has been read, so the resident memory stays bounded by a
//! few windows, however large the file.
//!
//! Unmapping is work for the kernel, so a helper thread does it, and maps the next window while
//! the current one is parsed. At most three windows are mapped at a time: the one being read,
//! the one handed over, and the one being mapped. The windows are not pre-faulted: with
//! `MAP_POPULATE` the kernel set up their page tables page by page on the helper thread, which
//! cost more than the parser's own page faults do, each of which maps 16 pages of a file in the
//! page cache at once ("fault-around"). Measured on 10⁶ poses, every run's input warmed
//! (`bench/ab.sh`, three runs of 31-41 rounds), with → without: medians 85.3 → 82.5,
//! 87.0 → 80.5 and 85.3 → 80.5 ms.
//!
//! Caveat of every memory-mapped reader: if another program truncates the file while it is
//! being read, the operating system stops the process (SIGBUS). Files that grow while being
//! read are fine: the size is checked again at the end of the mapped part, and what was
//! appended is mapped too. [`super::open`] uses this reader only for regular files of at least
//! [`MIN_MAPPED_BYTES`]; smaller files, pipes and stdin are read with `read`.

use memmap2::{Mmap, MmapOptions};
use std::fs::File;
use std::io::{BufRead, Read};
use std::sync::mpsc::{sync_channel, Receiver, Sender};

/// Bytes mapped at a time (a multiple of every page size in use). Fewer, larger windows are
/// fewer calls to map and unmap, each of which interrupts the other core to flush its address
/// translations: on 10^6 poses (`bench/ab.sh`, 41 interleaved runs twice) 8 MiB windows took
/// `learn`'s median wall time 66.7 -> 65.8 and 68.7 -> 65.6 ms against 2 MiB ones, for a
/// peak RSS of 25 MB instead of 18 MB.
pub const WINDOW: usize = 8 << 20;
/// Files smaller than this \[bytes\] are read with `read`: for them the copy is cheap and a
/// mapping would only add system calls.
pub const MIN_MAPPED_BYTES: u64 = 16 << 20;

/// A mapped window of the file.
struct Window {
    map: Mmap,
    /// Offset in the window of the first byte not read before it was mapped.
    pos: usize,
    /// File offset just after the window (where the next one starts).
    next: u64,
}

/// Map the window of `file` that starts at file offset `next`; `None` at the end of the file.
fn map_window(file: &File, next: u64) -> std::io::Result<Option<Window>> {
    let len = file.metadata()?.len();
    if next >= len {
        return Ok(None);
    }
    // Mappings start at page boundaries; after a file grew, `next` may not be on one.
    let start = next - next % page_size();
    let n = (len - start).min(WINDOW as u64) as usize;
    // SAFETY: the mapping is read-only and private to this reader; the only hazard is a
    // concurrent truncation of the file, which the module documentation states (SIGBUS).
    let map = unsafe { MmapOptions::new().offset(start).len(n).map(file)? };
    Ok(Some(Window {
        map,
        pos: (next - start) as usize,
        next: start + n as u64,
    }))
}

/// The helper thread's ends of the hand-over: windows mapped ahead (then `None` at the end of
/// the file, or an error), and windows given back to be unmapped.
struct Ahead {
    windows: Receiver<std::io::Result<Option<Window>>>,
    retired: Sender<Mmap>,
}

impl Ahead {
    /// Start a helper thread mapping `file` from its start; `None` if the file cannot be
    /// shared with it (the reader then maps on its own thread).
    fn spawn(file: &File) -> Option<Ahead> {
        let file = file.try_clone().ok()?;
        let (tx, windows) = sync_channel(1);
        let (retired, unmap) = std::sync::mpsc::channel::<Mmap>();
        std::thread::Builder::new()
            .name("objmodel-map".into())
            .spawn(move || {
                let mut next = 0;
                loop {
                    // Unmap what the reader is done with before mapping more.
                    while unmap.try_recv().is_ok() {}
                    let w = map_window(&file, next);
                    let go_on = matches!(w, Ok(Some(_)));
                    if let Ok(Some(w)) = &w {
                        next = w.next;
                    }
                    if tx.send(w).is_err() || !go_on {
                        break;
                    }
                }
                // The reader's last windows, once it is done with them.
                while unmap.recv().is_ok() {}
            })
            .ok()?;
        Some(Ahead { windows, retired })
    }
}

/// A `BufRead` over a file, one mapped window at a time.
pub struct MappedFile {
    file: File,
    /// The current window (mapped from a page-aligned offset).
    map: Option<Mmap>,
    /// Next unread byte in the window.
    pos: usize,
    /// File offset just after the current window (where the next one starts).
    next: u64,
    /// The helper thread, until it reached the end of the file (what was appended after that
    /// is mapped on the reader's thread).
    ahead: Option<Ahead>,
}

impl MappedFile {
    /// A reader of `file` from its start.
    pub fn new(file: File) -> Self {
        let ahead = Ahead::spawn(&file);
        Self {
            file,
            map: None,
            pos: 0,
            next: 0,
            ahead,
        }
    }

    /// Take the window after the current one, if the file has bytes there. Returns false at
    /// the end of the file.
    fn advance(&mut self) -> std::io::Result<bool> {
        // Give the current window back first, so that few are resident.
        if let Some(old) = self.map.take() {
            if let Some(a) = &self.ahead {
                let _ = a.retired.send(old);
            }
        }
        let w = match self.ahead.as_ref().map(|a| a.windows.recv()) {
            Some(Ok(Ok(Some(w)))) => Some(w),
            Some(Ok(Err(e))) => {
                self.ahead = None;
                return Err(e);
            }
            // The helper is at the end of the file (or gone): map on this thread from here.
            Some(Ok(Ok(None)) | Err(_)) | None => {
                self.ahead = None;
                map_window(&self.file, self.next)?
            }
        };
        let Some(w) = w else {
            return Ok(false);
        };
        self.pos = w.pos;
        self.next = w.next;
        self.map = Some(w.map);
        Ok(true)
    }
}

/// The largest page size the offsets of the mappings must be multiples of (64 KiB covers
/// every common system; [`WINDOW`] is a multiple of it).
fn page_size() -> u64 {
    1 << 16
}

impl Read for MappedFile {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let avail = self.fill_buf()?;
        let n = avail.len().min(buf.len());
        buf[..n].copy_from_slice(&avail[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl BufRead for MappedFile {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        let exhausted = self.map.as_ref().is_none_or(|m| self.pos >= m.len());
        if exhausted && !self.advance()? {
            return Ok(&[]);
        }
        let m = self.map.as_ref().expect("a window after advance");
        Ok(&m[self.pos..])
    }

    fn consume(&mut self, amt: usize) {
        self.pos += amt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    #[test]
    fn reads_a_file_across_windows_byte_for_byte() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let path = dir.join("f.bin");
        // Two and a half windows of a pattern that differs at every offset modulo 251.
        let data: Vec<u8> = (0..WINDOW * 5 / 2).map(|i| (i % 251) as u8).collect();
        std::fs::File::create(&path)
            .unwrap()
            .write_all(&data)
            .unwrap();
        let mut r = MappedFile::new(File::open(&path).unwrap());
        let mut got = Vec::new();
        // Consume in odd-sized steps so that the steps straddle the window boundaries.
        loop {
            let b = r.fill_buf().unwrap();
            if b.is_empty() {
                break;
            }
            let n = b.len().min(1_000_003);
            got.extend_from_slice(&b[..n]);
            r.consume(n);
        }
        assert_eq!(got.len(), data.len());
        assert!(got == data);
        // Bytes appended after the end was reached are read on the next call.
        std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .unwrap()
            .write_all(b"tail")
            .unwrap();
        let mut tail = String::new();
        r.read_to_string(&mut tail).unwrap();
        assert_eq!(tail, "tail");
    }
}
