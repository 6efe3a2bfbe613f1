//! nendo-devices' integration tests, one binary: decoders against corrupted streams and fuzzing,
//! the emulated devices on pseudo-terminals, the stream reader, traces.

mod corruption;
mod emulated_devices;
mod fuzz;
mod recording;
mod startup;
mod stream;
mod support;
mod trace;
