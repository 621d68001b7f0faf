//! Every decompression a bag reader does, streamed and capped (issue 27):
//! ROS 1 bz2/lz4 chunks, MCAP zstd/lz4 chunks (inside the `mcap` crate,
//! bounded by its record length limit and counted here), rosbag2 zstd per
//! message and per file.
//!
//! Two caps from [`crate::tolerances`]: one block (a message, a chunk) at most
//! [`MAX_BAG_MESSAGE_BYTES`] after decompression, so one block never takes
//! more memory than that; one file at most `max(MIN_BAG_FILE_OUTPUT_BYTES,
//! MAX_BAG_EXPANSION x its size)` decompressed in all, so a bomb of small
//! chunks stops after a bounded amount of work. Output is read in pieces and
//! counted as it comes: nothing is allocated from a declared size alone.

use crate::diagnostic::{Error, Result};
use crate::tolerances::{MAX_BAG_EXPANSION, MAX_BAG_MESSAGE_BYTES, MIN_BAG_FILE_OUTPUT_BYTES};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// The decompression caps of one read (defaults from `tolerances`; a test or
/// a library caller may lower them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BagLimits {
    /// Largest message or chunk after decompression (bytes).
    pub block_bytes: usize,
    /// A file decompresses to at most this many times its size in all...
    pub expansion: u64,
    /// ... or this many bytes, whichever is larger.
    pub min_file_output: u64,
}

impl Default for BagLimits {
    fn default() -> Self {
        BagLimits {
            block_bytes: MAX_BAG_MESSAGE_BYTES,
            expansion: MAX_BAG_EXPANSION,
            min_file_output: MIN_BAG_FILE_OUTPUT_BYTES,
        }
    }
}

/// What one file may still decompress to.
#[derive(Debug, Clone)]
pub(super) struct Budget {
    pub limits: BagLimits,
    cap: u64,
    used: u64,
    file: PathBuf,
}

/// Bytes decompressed between two checks of the caps.
const PIECE: usize = 1 << 20;

impl Budget {
    /// The budget of the file at `file`, `len` bytes long.
    pub fn new(file: &Path, len: u64, limits: BagLimits) -> Self {
        Budget {
            limits,
            cap: limits
                .min_file_output
                .max(len.saturating_mul(limits.expansion)),
            used: 0,
            file: file.to_path_buf(),
        }
    }

    /// The whole-file cap (bytes).
    pub fn cap(&self) -> u64 {
        self.cap
    }

    /// Count `n` more decompressed bytes; a `limit` error past the cap.
    pub fn take(&mut self, n: u64, what: &str) -> Result<()> {
        self.used = self.used.saturating_add(n);
        if self.used > self.cap {
            return Err(Error::limit(format!(
                "{what}: the file decompresses to more than {} bytes in all (at most {}x its size, or {} bytes; issue 27's decompression cap): a decompression bomb?",
                self.cap, self.limits.expansion, self.limits.min_file_output
            ))
            .in_file(&self.file));
        }
        Ok(())
    }

    /// Decompress `r` (one message or chunk, `what` naming it) into memory,
    /// at most [`BagLimits::block_bytes`] and the file's budget.
    pub fn inflate(&mut self, r: impl Read, what: &str) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        self.inflate_into(r, &mut out, self.limits.block_bytes as u64, what)?;
        Ok(out)
    }

    /// Decompress `r` into `out`, at most `cap` bytes and the file's budget;
    /// the bytes written.
    pub fn inflate_into(
        &mut self,
        mut r: impl Read,
        out: &mut dyn Write,
        cap: u64,
        what: &str,
    ) -> Result<u64> {
        let mut buf = vec![0u8; PIECE];
        let mut total = 0u64;
        loop {
            let n = match r.read(&mut buf) {
                Ok(0) => return Ok(total),
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => {
                    return Err(
                        Error::parse(format!("{what}: cannot decompress: {e}")).in_file(&self.file)
                    )
                }
            };
            total += n as u64;
            if total > cap {
                return Err(Error::limit(format!(
                    "{what}: decompresses to more than {cap} bytes (the largest block a bag reader takes: a decompression bomb?)"
                ))
                .in_file(&self.file));
            }
            self.take(n as u64, what)?;
            out.write_all(&buf[..n])
                .map_err(|e| Error::io(&self.file, &e))?;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unzstd(z: &[u8]) -> impl Read + '_ {
        zstd::stream::read::Decoder::new(z).unwrap()
    }

    fn small() -> BagLimits {
        BagLimits {
            block_bytes: 4 << 20,
            expansion: 10,
            min_file_output: 6 << 20,
        }
    }

    #[test]
    fn a_block_past_its_cap_stops_while_decompressing() {
        let zeros = vec![0u8; 5 << 20];
        let z = zstd::encode_all(zeros.as_slice(), 3).unwrap();
        let mut b = Budget::new(Path::new("x.db3"), 100, small());
        let e = b.inflate(unzstd(&z), "message").unwrap_err();
        assert!(
            e.message.contains("more than 4194304 bytes"),
            "{}",
            e.message
        );
    }

    #[test]
    fn the_file_budget_adds_up_blocks() {
        let zeros = vec![0u8; 3 << 20];
        let z = zstd::encode_all(zeros.as_slice(), 3).unwrap();
        let mut b = Budget::new(Path::new("x.db3"), 100, small());
        assert_eq!(b.cap(), 6 << 20);
        b.inflate(unzstd(&z), "message 1").unwrap();
        b.inflate(unzstd(&z), "message 2").unwrap();
        let e = b.inflate(unzstd(&z), "message 3").unwrap_err();
        assert!(e.message.contains("in all"), "{}", e.message);
        // A large file's cap follows its size.
        assert_eq!(
            Budget::new(Path::new("y"), 1 << 30, small()).cap(),
            10 << 30
        );
    }
}
