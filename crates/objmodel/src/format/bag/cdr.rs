//! OMG CDR, the serialisation of ROS 2 messages in a bag (message encoding `cdr`): a 4-byte
//! encapsulation header, then the fields in order, each primitive aligned to its size
//! (counted from the end of the header), in the byte order the header names.
//!
//! Supported encapsulations: `CDR_BE` (0x0000) and `CDR_LE` (0x0001), what every ROS 2
//! middleware writes, and plain XCDR2 (`CDR2_BE` 0x0006, `CDR2_LE` 0x0007), where 8-byte
//! primitives are aligned to 4. Parameter lists (PL_CDR) and delimited XCDR2 are not needed
//! by the message types read here and are refused.

use std::fmt;

/// What is wrong with a CDR message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CdrError(pub String);

impl fmt::Display for CdrError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Result of decoding CDR.
pub type CdrResult<T> = std::result::Result<T, CdrError>;

/// A cursor over one CDR message.
#[derive(Clone, Debug)]
pub struct CdrReader<'a> {
    /// The message after its encapsulation header.
    body: &'a [u8],
    pos: usize,
    little_endian: bool,
    /// Largest alignment of a primitive: 8 in XCDR1, 4 in XCDR2.
    max_align: usize,
}

impl<'a> CdrReader<'a> {
    /// A reader of `message`, encapsulation header included.
    pub fn new(message: &'a [u8]) -> CdrResult<Self> {
        let Some((header, body)) = message.split_first_chunk::<4>() else {
            return Err(CdrError(format!(
                "{} bytes: too short for a CDR encapsulation header",
                message.len()
            )));
        };
        let (little_endian, max_align) = match (header[0], header[1]) {
            (0, 0x00) => (false, 8),
            (0, 0x01) => (true, 8),
            (0, 0x06) => (false, 4),
            (0, 0x07) => (true, 4),
            (a, b) => {
                return Err(CdrError(format!(
                    "unsupported CDR encapsulation 0x{a:02x}{b:02x} (read: CDR_BE, CDR_LE, \
                     plain CDR2_BE/LE)"
                )))
            }
        };
        Ok(Self {
            body,
            pos: 0,
            little_endian,
            max_align,
        })
    }

    /// Whether the message is little-endian.
    pub fn is_little_endian(&self) -> bool {
        self.little_endian
    }

    /// The next `n` bytes, aligned to `align` (capped at the encapsulation's largest).
    fn take<const N: usize>(&mut self, what: &str) -> CdrResult<[u8; N]> {
        let align = N.min(self.max_align);
        let start = self.pos.div_ceil(align) * align;
        match self.body.get(start..start + N) {
            Some(b) => {
                self.pos = start + N;
                Ok(b.try_into().expect("N bytes"))
            }
            None => Err(self.end(what)),
        }
    }

    fn end(&self, what: &str) -> CdrError {
        CdrError(format!(
            "message ends at byte {} of its body, in the middle of {what}",
            self.body.len()
        ))
    }

    /// A `uint8` (or `bool`, `char`).
    pub fn u8(&mut self, what: &str) -> CdrResult<u8> {
        Ok(self.take::<1>(what)?[0])
    }

    /// A `uint32`.
    pub fn u32(&mut self, what: &str) -> CdrResult<u32> {
        let b = self.take::<4>(what)?;
        Ok(if self.little_endian {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    /// An `int32`.
    pub fn i32(&mut self, what: &str) -> CdrResult<i32> {
        Ok(self.u32(what)? as i32)
    }

    /// A `float64`.
    pub fn f64(&mut self, what: &str) -> CdrResult<f64> {
        let b = self.take::<8>(what)?;
        Ok(if self.little_endian {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    /// `N` consecutive `float64`s (a fixed array, e.g. a point or a covariance).
    pub fn f64s<const N: usize>(&mut self, what: &str) -> CdrResult<[f64; N]> {
        let mut out = [0.0; N];
        for x in &mut out {
            *x = self.f64(what)?;
        }
        Ok(out)
    }

    /// A `string`: its length (terminating NUL included), its bytes, the NUL. Invalid UTF-8
    /// is replaced (frame names are ASCII).
    pub fn string(&mut self, what: &str) -> CdrResult<String> {
        Ok(String::from_utf8_lossy(self.str_bytes(what)?).into_owned())
    }

    /// A `string`'s bytes, borrowed from the message, without its terminating NUL.
    pub fn str_bytes(&mut self, what: &str) -> CdrResult<&'a [u8]> {
        let n = self.u32(what)? as usize;
        let Some(bytes) = self.body.get(self.pos..self.pos.saturating_add(n)) else {
            return Err(self.end(what));
        };
        self.pos += n;
        Ok(bytes.strip_suffix(&[0]).unwrap_or(bytes))
    }

    /// The length of a sequence whose elements take at least `min_element_bytes` each,
    /// checked against what is left of the message (a corrupt length cannot make the caller
    /// allocate more than the message holds).
    pub fn sequence_len(&mut self, min_element_bytes: usize, what: &str) -> CdrResult<usize> {
        let n = self.u32(what)? as usize;
        let left = self.body.len().saturating_sub(self.pos);
        if n.saturating_mul(min_element_bytes.max(1)) > left {
            return Err(CdrError(format!(
                "{what}: a sequence of {n} elements does not fit in the {left} bytes left"
            )));
        }
        Ok(n)
    }
}
