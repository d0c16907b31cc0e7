//! `cargo fuzz run rig`: rig files through magbench's parser and validator.
#![no_main]

use libfuzzer_sys::fuzz_target;
use xtask::fuzz::Target;

fuzz_target!(|data: &[u8]| {
    // an `Err` is a fine answer; a panic, an abort or a hang is a bug
    let _ = Target::Rig.run(data);
});
