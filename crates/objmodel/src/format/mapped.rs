//! Reading a large regular file through memory-mapped windows instead of `read` calls.
//!
//! `read` copies every byte from the kernel's page cache into the reader's buffer; for a
//! 100 MB pose file that copy was about a fifth of the parsing thread's time. Mapping the file
//! lets the parser read the page cache directly. The file is mapped one [`WINDOW`] at a time
//! (pre-faulted with `MAP_POPULATE`) and each window is unmapped before the next is mapped, so
//! the resident memory stays bounded by the window, however large the file.
//!
//! Caveat of every memory-mapped reader: if another program truncates the file while it is
//! being read, the operating system stops the process (SIGBUS). Files that grow while being
//! read are fine: the size is checked again at the end of the mapped part, and what was
//! appended is mapped too. [`super::open`] uses this reader only for regular files of at least
//! [`MIN_MAPPED_BYTES`]; smaller files, pipes and stdin are read with `read`.

use memmap2::{Mmap, MmapOptions};
use std::fs::File;
use std::io::{BufRead, Read};

/// Bytes mapped at a time (a multiple of every page size in use).
pub const WINDOW: usize = 4 << 20;
/// Files smaller than this \[bytes\] are read with `read`: for them the copy is cheap and a
/// mapping would only add system calls.
pub const MIN_MAPPED_BYTES: u64 = 16 << 20;

/// A `BufRead` over a file, one mapped window at a time.
pub struct MappedFile {
    file: File,
    /// The current window (mapped from a page-aligned offset).
    map: Option<Mmap>,
    /// Next unread byte in the window.
    pos: usize,
    /// File offset just after the current window (where the next one starts).
    next: u64,
}

impl MappedFile {
    /// A reader of `file` from its start.
    pub fn new(file: File) -> Self {
        Self {
            file,
            map: None,
            pos: 0,
            next: 0,
        }
    }

    /// Map the window after the current one, if the file has bytes there. Returns false at the
    /// end of the file.
    fn advance(&mut self) -> std::io::Result<bool> {
        // Unmap first, so that at most one window is resident.
        self.map = None;
        let len = self.file.metadata()?.len();
        if self.next >= len {
            return Ok(false);
        }
        // Mappings start at page boundaries; after a file grew, `next` may not be on one.
        let start = self.next - self.next % page_size();
        let n = (len - start).min(WINDOW as u64) as usize;
        // SAFETY: the mapping is read-only and private to this reader; the only hazard is a
        // concurrent truncation of the file, which the module documentation states (SIGBUS).
        let map = unsafe {
            MmapOptions::new()
                .offset(start)
                .len(n)
                .populate()
                .map(&self.file)?
        };
        self.pos = (self.next - start) as usize;
        self.next = start + n as u64;
        self.map = Some(map);
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
        let dir = std::env::temp_dir().join(format!("objmodel-mapped-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
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
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn open_maps_a_large_file_and_reads_every_pose() {
        let dir = std::env::temp_dir().join(format!("objmodel-mapped-open-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.tum");
        // Enough lines to pass MIN_MAPPED_BYTES, so lines straddle several window boundaries.
        let mut text = String::from("# t x y z qx qy qz qw\n");
        let mut k = 0u64;
        while (text.len() as u64) < MIN_MAPPED_BYTES + WINDOW as u64 / 2 {
            let t = k as f64 / 30.0;
            text.push_str(&format!(
                "{t:.6} {:.6} -0.25 1.5 0 0 0.6 0.8\n",
                k as f64 * 1e-6
            ));
            k += 1;
        }
        std::fs::write(&path, &text).unwrap();
        let poses: Vec<_> = super::super::open(&path)
            .unwrap()
            .collect::<crate::Result<_>>()
            .unwrap();
        assert_eq!(poses.len() as u64, k);
        for (i, p) in poses.iter().enumerate() {
            assert!(
                (p.pose.translation.vector.x - i as f64 * 1e-6).abs() < 1e-9,
                "pose {i}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
