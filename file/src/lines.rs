//! Reading text one line at a time with a bound on what is held: [`read_line_bounded`] keeps at
//! most `limit` bytes of a line, so a line of any length — or one that never ends, as
//! `/dev/zero` or an endless pipe gives — costs at most the limit in memory. What happens to
//! the rest of an over-long line is the caller's choice ([`Overlong`]): a batch protocol reads
//! it through to its newline and answers the next line; a file that is refused whole (an
//! operations file) stops at once, having read `limit + 1` bytes of it.

use std::io::{self, BufRead};

/// What [`read_line_bounded`] does with a line longer than its limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overlong {
    /// Reads on to its newline (or the end) without keeping it: the next call reads the next
    /// line. An endless line is read to the end of the input.
    SkipThrough,
    /// Stops reading where the limit is passed: the input is left in the middle of the line.
    Stop,
}

/// One line as [`read_line_bounded`] read it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Line {
    /// The input ended before another byte.
    End,
    /// A line of at most the limit, now in the buffer (without its newline and a `\r` before
    /// it); `newline`: it ended with one (else it ended the input).
    Text {
        /// The line ended with a newline.
        newline: bool,
    },
    /// A line over the limit, not kept: `bytes` is how many of its bytes were read (all of
    /// them, without the newline, for [`Overlong::SkipThrough`]; more than the limit for
    /// [`Overlong::Stop`]).
    TooLong {
        /// Bytes of the line read.
        bytes: u64,
    },
}

/// Reads one line of `input` into `buf` (cleared first), holding at most `limit` bytes of it
/// (see the module docs). A read interrupted by a signal is retried.
///
/// # Errors
/// The input's read error.
pub fn read_line_bounded(
    input: &mut impl BufRead,
    buf: &mut Vec<u8>,
    limit: usize,
    overlong: Overlong,
) -> io::Result<Line> {
    buf.clear();
    let mut any = false;
    let mut over: Option<u64> = None;
    let mut newline = false;
    loop {
        let available = match input.fill_buf() {
            Ok(b) => b,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if available.is_empty() {
            break;
        }
        any = true;
        let at = available.iter().position(|&b| b == b'\n');
        let part = &available[..at.unwrap_or(available.len())];
        let len = part.len();
        if let Some(n) = over.as_mut() {
            *n += len as u64;
        } else if buf.len() + len > limit {
            let bytes = (buf.len() + len) as u64;
            buf.clear();
            buf.shrink_to(limit.min(1 << 16));
            if overlong == Overlong::Stop {
                input.consume(len);
                return Ok(Line::TooLong { bytes });
            }
            over = Some(bytes);
        } else {
            buf.extend_from_slice(part);
        }
        input.consume(len + usize::from(at.is_some()));
        if at.is_some() {
            newline = true;
            break;
        }
    }
    if let Some(bytes) = over {
        return Ok(Line::TooLong { bytes });
    }
    if !any {
        return Ok(Line::End);
    }
    if buf.last() == Some(&b'\r') {
        buf.pop();
    }
    Ok(Line::Text { newline })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every line of `text` read with a 7-byte buffer (lines cross buffer boundaries).
    fn lines(text: &[u8], limit: usize, overlong: Overlong) -> Vec<(Line, Vec<u8>)> {
        let mut input = io::BufReader::with_capacity(7, text);
        let mut buf = Vec::new();
        let mut out = Vec::new();
        loop {
            let line = read_line_bounded(&mut input, &mut buf, limit, overlong).expect("memory");
            if line == Line::End {
                return out;
            }
            out.push((line, buf.clone()));
            if matches!(line, Line::TooLong { .. }) && overlong == Overlong::Stop {
                return out;
            }
        }
    }

    #[test]
    fn lines_within_the_limit_are_kept_and_a_longer_one_is_skipped_or_stops_the_reading() {
        let text = b"ab\r\n0123456789abcdef\n\nlast";
        let through = lines(text, 10, Overlong::SkipThrough);
        assert_eq!(
            through,
            [
                (Line::Text { newline: true }, b"ab".to_vec()),
                (Line::TooLong { bytes: 16 }, Vec::new()),
                (Line::Text { newline: true }, Vec::new()),
                (Line::Text { newline: false }, b"last".to_vec()),
            ]
        );
        let stop = lines(text, 10, Overlong::Stop);
        assert_eq!(stop.len(), 2);
        assert!(matches!(stop[1].0, Line::TooLong { bytes } if bytes > 10 && bytes <= 16));
        // A line of exactly the limit is kept.
        assert_eq!(
            lines(b"0123456789", 10, Overlong::Stop),
            [(Line::Text { newline: false }, b"0123456789".to_vec())]
        );
    }

    #[test]
    fn an_endless_line_stops_after_the_limit() {
        // `/dev/zero` as a file: `Stop` returns after reading little more than the limit.
        let mut zero = io::BufReader::with_capacity(1 << 16, io::repeat(0));
        let mut buf = Vec::new();
        let line = read_line_bounded(&mut zero, &mut buf, 1 << 20, Overlong::Stop).expect("read");
        assert!(matches!(line, Line::TooLong { bytes } if bytes <= (1 << 20) + (1 << 16)));
        assert!(buf.capacity() <= 1 << 20);
    }
}
