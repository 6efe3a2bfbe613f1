//! nendo-devices: glove and tracker input.
