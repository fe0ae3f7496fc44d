//! `.tlog` recording: each record is an 8-byte big-endian count of microseconds since the Unix epoch followed by
//! the raw MAVLink frame, the format pymavlink's `mavutil.mavlink_connection(path)` reads.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

pub struct TlogWriter {
    out: BufWriter<File>,
}

impl TlogWriter {
    pub fn create(path: &Path) -> io::Result<Self> {
        Ok(Self {
            out: BufWriter::new(File::create(path)?),
        })
    }

    /// Records one frame stamped with the current wall-clock time.
    pub fn record(&mut self, frame: &[u8]) -> io::Result<()> {
        let us = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_micros() as u64)
            .unwrap_or(0);
        self.record_at(us, frame)
    }

    pub fn record_at(&mut self, unix_us: u64, frame: &[u8]) -> io::Result<()> {
        self.out.write_all(&unix_us.to_be_bytes())?;
        self.out.write_all(frame)
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

impl Drop for TlogWriter {
    fn drop(&mut self) {
        let _ = self.out.flush();
    }
}

/// Reads a `.tlog` back: (timestamp µs, frame bytes) per record; the frame length comes from its header.
pub fn read_tlog(bytes: &[u8]) -> Result<Vec<(u64, Vec<u8>)>, String> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes.len() < i + 10 {
            return Err(format!("truncated record at byte {i}"));
        }
        let mut ts = [0u8; 8];
        ts.copy_from_slice(&bytes[i..i + 8]);
        let f = &bytes[i + 8..];
        let len = match f[0] {
            0xFE => 8 + usize::from(f[1]),
            0xFD => 12 + usize::from(f[1]) + if f[2] & 1 != 0 { 13 } else { 0 },
            other => {
                return Err(format!(
                    "byte {}: 0x{other:02x} is no MAVLink start marker",
                    i + 8
                ))
            }
        };
        if f.len() < len {
            return Err(format!("truncated frame at byte {}", i + 8));
        }
        out.push((u64::from_be_bytes(ts), f[..len].to_vec()));
        i += 8 + len;
    }
    Ok(out)
}
