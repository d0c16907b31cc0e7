//! The rig emulator: the device side of a coil-and-camera rig, in its own process.

pub mod render;
