//! The incremental byte-stream decoder shared by every serial protocol.
//!
//! A protocol describes its record framing through [`Framing`]: given the bytes waiting at the
//! front of the stream, it says whether they start a record (and how long it is), cannot yet
//! tell, or do not start a record. [`StreamDecoder`] drives any framing: push bytes in, get
//! records out, with counters of what was skipped.
//!
//! Resynchronisation is within one record: when the front bytes are not a valid record, exactly
//! one byte is dropped and the hunt for the next header starts at the byte after it, so a
//! corrupt record costs at most itself (plus any false headers inside it, which fail their own
//! checks). Bytes are never re-read more than once per candidate header, and the decoder never
//! holds more than one record's worth of bytes waiting for a decision.

/// Counters of a decoder: what came in, what was accepted, what was thrown away.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DecodeStats {
    /// Bytes pushed in.
    pub bytes_in: u64,
    /// Records accepted.
    pub records: u64,
    /// Bytes that were part of accepted records.
    pub record_bytes: u64,
    /// Bytes discarded while hunting for a valid record.
    pub skipped_bytes: u64,
    /// Candidate records that had a valid header but failed a check (checksum, terminator,
    /// phasing bit, value range): each is a bad frame dropped.
    pub rejected: u64,
    /// Times the decoder lost synchronisation (went from accepting records to discarding bytes).
    pub resyncs: u64,
}

impl DecodeStats {
    /// Adds another decoder's counters (for sources that restarted their decoder).
    pub fn merge(&mut self, other: &DecodeStats) {
        self.bytes_in += other.bytes_in;
        self.records += other.records;
        self.record_bytes += other.record_bytes;
        self.skipped_bytes += other.skipped_bytes;
        self.rejected += other.rejected;
        self.resyncs += other.resyncs;
    }
}

/// What a framing makes of the bytes at the front of the stream.
#[derive(Debug, Clone, PartialEq)]
pub enum Frame<R> {
    /// Too few bytes to decide; nothing is consumed.
    NeedMore,
    /// The first byte cannot start a record (not a header byte): skip it.
    NotHeader,
    /// A header was found but the candidate record fails a check: drop its first byte and hunt.
    Reject,
    /// A valid record of this many bytes.
    Record(R, usize),
}

/// A protocol's record framing: a pure function of the bytes at the front of the stream.
pub trait Framing {
    /// The decoded record.
    type Record;
    /// Decides about the bytes at the front of the stream (`window` is never empty).
    fn frame(&self, window: &[u8]) -> Frame<Self::Record>;
}

/// Drives a [`Framing`] over a byte stream delivered in arbitrary pieces.
#[derive(Debug, Clone)]
pub struct StreamDecoder<F> {
    framing: F,
    buf: Vec<u8>,
    start: usize,
    in_sync: bool,
    stats: DecodeStats,
}

impl<F: Framing> StreamDecoder<F> {
    /// A decoder with nothing buffered.
    pub fn new(framing: F) -> Self {
        StreamDecoder {
            framing,
            buf: Vec::new(),
            start: 0,
            in_sync: true,
            stats: DecodeStats::default(),
        }
    }

    /// The framing (protocol configuration) in use.
    pub fn framing(&self) -> &F {
        &self.framing
    }

    /// Pushes bytes and appends every record completed by them to `out`.
    pub fn push(&mut self, bytes: &[u8], out: &mut Vec<F::Record>) {
        self.stats.bytes_in += bytes.len() as u64;
        self.buf.extend_from_slice(bytes);
        loop {
            let window = &self.buf[self.start..];
            if window.is_empty() {
                break;
            }
            match self.framing.frame(window) {
                Frame::NeedMore => break,
                Frame::NotHeader => self.discard(false),
                Frame::Reject => self.discard(true),
                Frame::Record(record, len) => {
                    debug_assert!(len > 0 && len <= window.len());
                    let len = len.clamp(1, window.len());
                    self.start += len;
                    self.stats.records += 1;
                    self.stats.record_bytes += len as u64;
                    self.in_sync = true;
                    out.push(record);
                }
            }
        }
        // Compact: keep only the undecided tail.
        if self.start > 0 {
            self.buf.drain(..self.start);
            self.start = 0;
        }
    }

    /// Pushes bytes and returns the records completed by them.
    pub fn decode(&mut self, bytes: &[u8]) -> Vec<F::Record> {
        let mut out = Vec::new();
        self.push(bytes, &mut out);
        out
    }

    fn discard(&mut self, rejected: bool) {
        self.start += 1;
        self.stats.skipped_bytes += 1;
        if rejected {
            self.stats.rejected += 1;
        }
        if self.in_sync {
            self.stats.resyncs += 1;
            self.in_sync = false;
        }
    }

    /// Bytes held waiting for the rest of a record.
    pub fn pending(&self) -> usize {
        self.buf.len() - self.start
    }

    /// The counters so far.
    pub fn stats(&self) -> DecodeStats {
        self.stats
    }

    /// Forgets buffered bytes (after a restart of the device); the counters are kept.
    pub fn clear(&mut self) {
        self.buf.clear();
        self.start = 0;
        self.in_sync = true;
    }
}
