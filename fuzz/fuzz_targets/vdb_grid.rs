//! OpenVDB files: the grid table and the dense read of a float grid.
#![no_main]
use libfuzzer_sys::fuzz_target;
fuzz_target!(|data: &[u8]| {
    let _ = photon::medium::vdb::grid_names(data);
    let _ = photon::medium::vdb::read_float_grid(data, "density", 1 << 24);
});
