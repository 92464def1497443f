//! Photometric files: `parse_ies` and `parse_eulumdat` must give a finite,
//! non-negative intensity distribution or an error naming a line.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| isorad_fuzz::parse_photometry(data));
