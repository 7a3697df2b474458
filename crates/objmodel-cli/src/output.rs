//! Standard output for every command: a reader that went away (`objmodel ... | head`) is an
//! error to report, not a panic.

/// Write `s` to standard output, reporting a closed pipe as an error instead of panicking.
pub fn out(s: &str) -> anyhow::Result<()> {
    out_bytes(s.as_bytes())
}

/// [`out`] for bytes.
pub fn out_bytes(b: &[u8]) -> anyhow::Result<()> {
    use std::io::Write;
    let mut o = std::io::stdout().lock();
    o.write_all(b)?;
    o.flush()?;
    Ok(())
}
