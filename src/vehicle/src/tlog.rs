//! `.tlog` recording: each record is an 8-byte big-endian count of microseconds since the Unix epoch followed by
//! the raw MAVLink frame, the format pymavlink's `mavutil.mavlink_connection(path)` reads. A record is handed to
//! the buffer in one write, so the buffer reaches the file only between records: a process killed at any point
//! leaves a file that ends on a frame boundary (it may lack the last unflushed records, never half of one).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

pub struct TlogWriter {
    out: BufWriter<File>,
    /// The record being assembled (timestamp + frame), reused.
    record: Vec<u8>,
    /// Writes are failing (a full disk): only the first failure of a run of them is returned, so the
    /// caller warns once, not once per frame.
    failing: bool,
}

impl TlogWriter {
    pub fn create(path: &Path) -> io::Result<Self> {
        Ok(Self {
            out: BufWriter::new(File::create(path)?),
            record: Vec::with_capacity(8 + 280),
            failing: false,
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

    /// Records one frame. An error is returned once per run of failing writes (a full disk fails every
    /// one until space comes back): the records meanwhile may be lost; after a flush that succeeds, the
    /// next failure is returned again.
    pub fn record_at(&mut self, unix_us: u64, frame: &[u8]) -> io::Result<()> {
        // One write per record: BufWriter flushes before a write that does not fit, never inside it (two
        // writes let a flush fall between a timestamp and its frame).
        self.record.clear();
        self.record.extend_from_slice(&unix_us.to_be_bytes());
        self.record.extend_from_slice(frame);
        // A write that only fills the buffer proves nothing about the disk: the failures end at a flush.
        match self.out.write_all(&self.record) {
            Ok(()) => Ok(()),
            Err(_) if self.failing => Ok(()),
            Err(e) => {
                self.failing = true;
                Err(e)
            }
        }
    }

    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()?;
        self.failing = false;
        Ok(())
    }
}

impl Drop for TlogWriter {
    fn drop(&mut self) {
        let _ = self.out.flush();
    }
}

/// Why a `.tlog` does not read back; `at` is the byte offset in the file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TlogError {
    #[error("truncated record at byte {at}")]
    TruncatedRecord { at: usize },
    #[error("byte {at}: 0x{byte:02x} is no MAVLink start marker")]
    NoStartMarker { at: usize, byte: u8 },
    #[error("truncated frame at byte {at}")]
    TruncatedFrame { at: usize },
}

/// Reads a `.tlog` back: (timestamp µs, frame bytes) per record; the frame length comes from its header.
pub fn read_tlog(bytes: &[u8]) -> Result<Vec<(u64, Vec<u8>)>, TlogError> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes.len() < i + 10 {
            return Err(TlogError::TruncatedRecord { at: i });
        }
        let mut ts = [0u8; 8];
        ts.copy_from_slice(&bytes[i..i + 8]);
        let f = &bytes[i + 8..];
        let len = match f[0] {
            0xFE => 8 + usize::from(f[1]),
            0xFD => 12 + usize::from(f[1]) + if f[2] & 1 != 0 { 13 } else { 0 },
            byte => return Err(TlogError::NoStartMarker { at: i + 8, byte }),
        };
        if f.len() < len {
            return Err(TlogError::TruncatedFrame { at: i + 8 });
        }
        out.push((u64::from_be_bytes(ts), f[..len].to_vec()));
        i += 8 + len;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frames of every length from a minimal v1 frame to a signed v2 one: a MAVLink-shaped header with the
    /// length byte right, the rest filler (read_tlog checks the framing, not the CRC).
    fn frame(i: usize) -> Vec<u8> {
        let len = i % 256;
        if i.is_multiple_of(3) {
            let mut f = vec![0xFE, len as u8];
            f.resize(8 + len, 0x55);
            f
        } else {
            let signed = i % 3 == 2;
            let mut f = vec![0xFD, len as u8, u8::from(signed)];
            f.resize(12 + len + if signed { 13 } else { 0 }, 0xAA);
            f
        }
    }

    /// A full disk (`/dev/full` fails every write with ENOSPC): one error for the whole run of failures,
    /// not one per frame.
    #[test]
    fn a_full_disk_fails_once_not_once_per_frame() {
        let Ok(mut w) = TlogWriter::create(Path::new("/dev/full")) else {
            return; // no /dev/full on this system
        };
        let errors = (0..10_000)
            .filter(|&i| w.record_at(i as u64, &frame(i)).is_err())
            .count();
        assert_eq!(errors, 1);
    }

    /// The process dies without flushing (no destructor runs): what reached the file ends on a record
    /// boundary, whatever the sizes around the buffer's 8 KiB.
    #[test]
    fn a_killed_writer_leaves_whole_records() {
        let dir = tempfile::TempDir::new().expect("temp dir");
        for records in [37, 100, 311, 1000] {
            let path = dir.path().join(format!("{records}.tlog"));
            let mut w = TlogWriter::create(&path).expect("create");
            for i in 0..records {
                w.record_at(i as u64, &frame(i)).expect("record");
            }
            // As a kill would: the buffer is lost, nothing is flushed.
            std::mem::forget(w);
            let bytes = std::fs::read(&path).expect("read");
            let got = read_tlog(&bytes).unwrap_or_else(|e| panic!("{records} records: {e}"));
            assert!(got.len() <= records);
            for (i, (ts, f)) in got.iter().enumerate() {
                assert_eq!((*ts, f), (i as u64, &frame(i)));
            }
            if records >= 311 {
                assert!(
                    !got.is_empty(),
                    "more than 8 KiB written: some records reached the file"
                );
            }
        }
    }
}
