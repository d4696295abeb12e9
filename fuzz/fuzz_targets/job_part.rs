//! The parts in a job's `parts/` folder: labelled job parts, and the bare sample and PPM parts
//! inside them. The first byte picks the reader (bit 0) and which checksums to make right
//! before reading (bit 1: the file's; bit 2: the bare part's inside a label), so that inputs
//! reach the decoders behind the checksums.
#![no_main]
use libfuzzer_sys::fuzz_target;

/// Overwrite the last 8 bytes of `bytes` with the FNV-1a 64 of the rest, as the writers do.
fn make_checksum_right(bytes: &mut [u8]) {
    if bytes.len() < 8 {
        return;
    }
    let (body, tail) = bytes.split_at_mut(bytes.len() - 8);
    let mut h = photon::hash::Fnv1a::default();
    h.write(body);
    tail.copy_from_slice(&h.finish().to_le_bytes());
}

fuzz_target!(|data: &[u8]| {
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    let mut bytes = rest.to_vec();
    let labelled = kind & 1 == 0;
    if labelled && kind & 4 != 0 && bytes.len() >= 24 {
        let label_len = u32::from_le_bytes(bytes[12..16].try_into().expect("4 bytes")) as usize;
        let end = bytes.len() - 8;
        if let Some(inner) = bytes.get_mut(16usize.saturating_add(label_len)..end) {
            make_checksum_right(inner);
        }
    }
    if kind & 2 != 0 {
        make_checksum_right(&mut bytes);
    }
    if labelled {
        if let Ok((label, part)) = photon::job::part_file::decode(&bytes) {
            let _ = (label.range, part.range(), part.scene_hash());
        }
    } else if let Ok(part) = photon::job::decode_part(&bytes) {
        let _ = (part.range(), part.scene_hash());
    }
});
