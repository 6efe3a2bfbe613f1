//! The serial transport: a thin layer over the `serialport` crate that turns its errors into
//! [`DeviceError`]s and adds the few exchanges the protocols need (send a command, wait for an
//! answer, drain a stream). Decoding is not done here.

use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

use serialport::SerialPort;

use crate::DeviceError;
use crate::decode::{Framing, StreamDecoder};

/// An open serial port.
pub struct SerialLink {
    port: Box<dyn SerialPort>,
    name: String,
    timeout: Duration,
}

impl std::fmt::Debug for SerialLink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SerialLink")
            .field("name", &self.name)
            .finish()
    }
}

impl SerialLink {
    /// Opens `path` at `baud`, 8N1, no flow control.
    pub fn open(path: &str, baud: u32) -> Result<SerialLink, DeviceError> {
        let timeout = Duration::from_millis(50);
        let port = serialport::new(path, baud)
            .timeout(timeout)
            .open()
            .map_err(|error| DeviceError::Open {
                port: path.to_string(),
                error,
            })?;
        Ok(SerialLink {
            port,
            name: path.to_string(),
            timeout,
        })
    }

    /// The port path.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn io(&self, error: std::io::Error) -> DeviceError {
        DeviceError::Io {
            device: self.name.clone(),
            error,
        }
    }

    /// Writes all bytes.
    pub fn send(&mut self, bytes: &[u8]) -> Result<(), DeviceError> {
        self.port.write_all(bytes).map_err(|e| self.io(e))?;
        self.port.flush().map_err(|e| self.io(e))
    }

    /// Reads what arrives within `timeout` (at least one byte, or none on timeout). A hang-up or
    /// end of file is an error: the device is gone.
    pub fn read_some(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize, DeviceError> {
        let timeout = timeout.max(Duration::from_millis(1));
        if timeout != self.timeout {
            self.port
                .set_timeout(timeout)
                .map_err(|e| self.io(e.into()))?;
            self.timeout = timeout;
        }
        match self.port.read(buf) {
            Ok(0) => Err(self.io(std::io::Error::new(
                ErrorKind::UnexpectedEof,
                "the port closed",
            ))),
            Ok(n) => Ok(n),
            Err(e) if e.kind() == ErrorKind::TimedOut || e.kind() == ErrorKind::Interrupted => {
                Ok(0)
            }
            Err(e) => Err(self.io(e)),
        }
    }

    /// Discards input until nothing has arrived for `quiet`, or `limit` has passed.
    pub fn drain(&mut self, quiet: Duration, limit: Duration) -> Result<(), DeviceError> {
        let end = Instant::now() + limit;
        let mut buf = [0u8; 512];
        while Instant::now() < end {
            if self.read_some(&mut buf, quiet)? == 0 {
                break;
            }
        }
        Ok(())
    }

    /// Reads until the bytes `answer` have arrived in order (anything before them is skipped),
    /// or fails after `timeout`.
    pub fn expect(
        &mut self,
        answer: &[u8],
        timeout: Duration,
        command: &str,
    ) -> Result<(), DeviceError> {
        let end = Instant::now() + timeout;
        let mut seen: Vec<u8> = Vec::new();
        let mut buf = [0u8; 256];
        loop {
            let now = Instant::now();
            if now >= end {
                return Err(self.timeout_error(command, timeout));
            }
            let n = self.read_some(&mut buf, end - now)?;
            seen.extend_from_slice(&buf[..n]);
            if seen.windows(answer.len()).any(|w| w == answer) {
                return Ok(());
            }
            if seen.len() > 4096 {
                return Err(DeviceError::BadAnswer {
                    device: self.name.clone(),
                    command: command.to_string(),
                    detail: format!(
                        "{} bytes without the expected answer {answer:02x?}",
                        seen.len()
                    ),
                });
            }
        }
    }

    /// Reads exactly `n` bytes within `timeout`.
    pub fn read_exact(
        &mut self,
        n: usize,
        timeout: Duration,
        command: &str,
    ) -> Result<Vec<u8>, DeviceError> {
        let end = Instant::now() + timeout;
        let mut out = vec![0u8; n];
        let mut have = 0;
        while have < n {
            let now = Instant::now();
            if now >= end {
                return Err(self.timeout_error(command, timeout));
            }
            have += self.read_some(&mut out[have..], end - now)?;
        }
        Ok(out)
    }

    /// Feeds input to `decoder` until it yields a record for which `accept` is true, or fails
    /// after `timeout`.
    pub fn await_record<F: Framing>(
        &mut self,
        decoder: &mut StreamDecoder<F>,
        timeout: Duration,
        command: &str,
        accept: impl Fn(&F::Record) -> bool,
    ) -> Result<F::Record, DeviceError> {
        let end = Instant::now() + timeout;
        let mut buf = [0u8; 256];
        let mut records = Vec::new();
        loop {
            let now = Instant::now();
            if now >= end {
                return Err(self.timeout_error(command, timeout));
            }
            let n = self.read_some(&mut buf, end - now)?;
            decoder.push(&buf[..n], &mut records);
            if let Some(i) = records.iter().position(&accept) {
                return Ok(records.swap_remove(i));
            }
            records.clear();
        }
    }

    fn timeout_error(&self, command: &str, timeout: Duration) -> DeviceError {
        DeviceError::Timeout {
            device: self.name.clone(),
            command: command.to_string(),
            millis: timeout.as_millis() as u64,
        }
    }
}
