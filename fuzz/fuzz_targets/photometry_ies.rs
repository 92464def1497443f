//! IES LM-63 files, as bytes read from disk: `parse_photometric_bytes`
//! must give a finite, non-negative intensity distribution or an error
//! naming a line.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| isorad_fuzz::parse_ies_bytes(data));
