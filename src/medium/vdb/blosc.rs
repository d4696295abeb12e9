//! Decoder for the Blosc1 container format (c-blosc 1.x, format version 2), as far as
//! OpenVDB uses it: LZ4 or uncompressed ("memcpyed") blocks with optional byte shuffle.
//!
//! Layout (c-blosc `README_HEADER.rst`): a 16-byte header
//! `version u8, versionlz u8, flags u8, typesize u8, nbytes u32, blocksize u32, cbytes u32`
//! (little endian), where `cbytes` counts the whole buffer including the header. Flags:
//! 0x01 byte shuffle, 0x02 memcpyed (the `nbytes` raw bytes follow the header), 0x04 bit
//! shuffle, 0x08 delta (reserved in 1.x), 0x10 "don't split", bits 5..7 the codec
//! (0 BloscLZ, 1 LZ4/LZ4HC, 2 Snappy, 3 Zlib, 4 Zstd). Otherwise the header is followed
//! by one `i32` start offset per block (`ceil(nbytes / blocksize)` blocks; the last one
//! holds the `nbytes % blocksize` leftover), each offset counted from the buffer start.
//! A block is `nsplits` streams, each an `i32` compressed length then the codec data; a
//! stream whose compressed length equals its decompressed length is stored raw. A full
//! block is split into `typesize` streams unless the 0x10 flag is set, `typesize > 16`
//! or `blocksize / typesize < 128`; a leftover block is never split. With byte shuffle
//! a block holds byte 0 of every element, then byte 1, and so on.

/// The Blosc1 header length, also the payload offset of a memcpyed buffer.
const HEADER_LEN: usize = 16;
const FLAG_SHUFFLE: u8 = 0x01;
const FLAG_MEMCPYED: u8 = 0x02;
const FLAG_BITSHUFFLE: u8 = 0x04;
const FLAG_DELTA: u8 = 0x08;
const FLAG_DONT_SPLIT: u8 = 0x10;
const CODEC_LZ4: u8 = 1;
const CODEC_NAMES: [&str; 8] = ["blosclz", "lz4", "snappy", "zlib", "zstd", "5", "6", "7"];
/// c-blosc's `MAX_SPLITS` and `MIN_BUFFERSIZE`: when a full block is split in streams.
const MAX_SPLITS: usize = 16;
const MIN_SPLIT_BUFFER: usize = 128;

/// Decompresses a Blosc1 buffer whose uncompressed size must not exceed `max_len`.
/// Errors are messages; the caller adds the file offset.
pub fn decompress(src: &[u8], max_len: usize) -> Result<Vec<u8>, String> {
    let header = src.get(..HEADER_LEN).ok_or_else(|| {
        format!(
            "a Blosc buffer needs a 16-byte header, got {} bytes",
            src.len()
        )
    })?;
    let (version, flags, typesize) = (header[0], header[2], usize::from(header[3]));
    let nbytes = le_u32(header, 4)?;
    let blocksize = le_u32(header, 8)?;
    let cbytes = le_u32(header, 12)?;
    if version == 0 || version > 2 {
        return Err(format!(
            "Blosc format version {version} is not supported (1 or 2)"
        ));
    }
    if cbytes != src.len() {
        return Err(format!(
            "Blosc header says {cbytes} compressed bytes, the chunk has {}",
            src.len()
        ));
    }
    if nbytes > max_len {
        return Err(format!(
            "Blosc chunk holds {nbytes} bytes, at most {max_len} expected"
        ));
    }
    if nbytes == 0 {
        return Ok(Vec::new());
    }
    if flags & FLAG_MEMCPYED != 0 {
        let end = HEADER_LEN
            .checked_add(nbytes)
            .ok_or("Blosc size overflows")?;
        return match src.get(HEADER_LEN..end) {
            Some(raw) if end == src.len() => Ok(raw.to_vec()),
            _ => Err(format!(
                "memcpyed Blosc chunk of {nbytes} bytes has {} payload bytes",
                src.len() - HEADER_LEN
            )),
        };
    }
    check_flags(flags, typesize, blocksize)?;
    let mut out = vec![0u8; nbytes];
    let mut scratch = vec![0u8; blocksize.min(nbytes)];
    for (index, block) in out.chunks_mut(blocksize).enumerate() {
        let start_pos = index
            .checked_mul(4)
            .and_then(|o| o.checked_add(HEADER_LEN))
            .ok_or("Blosc block count overflows")?;
        let start = usize::try_from(le_i32(src, start_pos)?)
            .map_err(|_| format!("Blosc block {index} has a negative start offset"))?;
        let leftover = block.len() < blocksize;
        let split = flags & FLAG_DONT_SPLIT == 0
            && typesize <= MAX_SPLITS
            && blocksize / typesize >= MIN_SPLIT_BUFFER
            && !leftover;
        let streams = if split { typesize } else { 1 };
        let shuffled = flags & FLAG_SHUFFLE != 0 && typesize > 1;
        let target = if shuffled {
            &mut scratch[..block.len()]
        } else {
            &mut *block
        };
        decode_block(src, start, target, streams)
            .map_err(|e| format!("Blosc block {index}: {e}"))?;
        if shuffled {
            unshuffle(&scratch[..block.len()], block, typesize);
        }
    }
    Ok(out)
}

/// Rejects the features OpenVDB never writes: codecs other than LZ4, bit shuffle, delta.
fn check_flags(flags: u8, typesize: usize, blocksize: usize) -> Result<(), String> {
    let codec = flags >> 5;
    if codec != CODEC_LZ4 {
        let name = CODEC_NAMES[usize::from(codec & 7)];
        return Err(format!(
            "Blosc codec '{name}' is not supported: only lz4 and uncompressed"
        ));
    }
    if flags & (FLAG_BITSHUFFLE | FLAG_DELTA) != 0 {
        return Err(format!(
            "Blosc flags {flags:#04x} ask for bit shuffle or delta, not supported"
        ));
    }
    if typesize == 0 || blocksize == 0 {
        return Err(format!(
            "Blosc typesize {typesize} and blocksize {blocksize} must be positive"
        ));
    }
    Ok(())
}

/// Decodes the `streams` equal parts of one block starting at `start` into `out`.
fn decode_block(src: &[u8], start: usize, out: &mut [u8], streams: usize) -> Result<(), String> {
    if !out.len().is_multiple_of(streams) {
        return Err(format!(
            "{} bytes do not split into {streams} streams",
            out.len()
        ));
    }
    let part = out.len() / streams;
    let mut pos = start;
    for stream in out.chunks_mut(part).take(streams) {
        let clen = usize::try_from(le_i32(src, pos)?).map_err(|_| "negative stream length")?;
        pos = pos.checked_add(4).ok_or("offset overflows")?;
        let end = pos.checked_add(clen).ok_or("stream length overflows")?;
        let data = src
            .get(pos..end)
            .ok_or_else(|| format!("stream of {clen} bytes at {pos} runs past the chunk end"))?;
        if clen == stream.len() {
            stream.copy_from_slice(data);
        } else {
            let n = lz4_flex::block::decompress_into(data, stream)
                .map_err(|e| format!("lz4 stream at {pos}: {e}"))?;
            if n != stream.len() {
                return Err(format!(
                    "lz4 stream at {pos} gave {n} bytes, {} expected",
                    stream.len()
                ));
            }
        }
        pos = end;
    }
    Ok(())
}

/// Undoes the byte shuffle: `src` holds byte `b` of element `e` at `b * count + e`;
/// trailing bytes that do not fill a whole element are stored unshuffled.
fn unshuffle(src: &[u8], dest: &mut [u8], typesize: usize) {
    let count = src.len() / typesize;
    let whole = count * typesize;
    for (e, element) in dest[..whole].chunks_exact_mut(typesize).enumerate() {
        for (b, byte) in element.iter_mut().enumerate() {
            *byte = src.get(b * count + e).copied().unwrap_or(0);
        }
    }
    dest[whole..].copy_from_slice(&src[whole..]);
}

fn le_u32(bytes: &[u8], pos: usize) -> Result<usize, String> {
    let word: [u8; 4] = pos
        .checked_add(4)
        .and_then(|end| bytes.get(pos..end))
        .and_then(|s| s.try_into().ok())
        .ok_or_else(|| {
            format!(
                "Blosc chunk of {} bytes ends inside the u32 at {pos}",
                bytes.len()
            )
        })?;
    usize::try_from(u32::from_le_bytes(word)).map_err(|_| "size does not fit usize".to_string())
}

fn le_i32(bytes: &[u8], pos: usize) -> Result<i32, String> {
    let word: [u8; 4] = pos
        .checked_add(4)
        .and_then(|end| bytes.get(pos..end))
        .and_then(|s| s.try_into().ok())
        .ok_or_else(|| {
            format!(
                "Blosc chunk of {} bytes ends inside the i32 at {pos}",
                bytes.len()
            )
        })?;
    Ok(i32::from_le_bytes(word))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(flags: u8, typesize: u8, nbytes: u32, blocksize: u32, cbytes: u32) -> Vec<u8> {
        let mut h = vec![2, 1, flags, typesize];
        for v in [nbytes, blocksize, cbytes] {
            h.extend_from_slice(&v.to_le_bytes());
        }
        h
    }

    #[test]
    fn memcpyed_buffer_is_copied() {
        let mut buf = header(FLAG_MEMCPYED | (CODEC_LZ4 << 5), 4, 8, 8, 24);
        buf.extend_from_slice(&[1, 2, 3, 4, 5, 6, 7, 8]);
        assert_eq!(decompress(&buf, 8).unwrap(), vec![1, 2, 3, 4, 5, 6, 7, 8]);
        assert!(decompress(&buf, 7).is_err());
    }

    #[test]
    fn shuffled_lz4_blocks_with_leftover_round_trip() {
        // Two elements of 4 bytes per block (blocksize 8) plus a 4-byte leftover block.
        let data: Vec<u8> = (0u8..20).collect();
        let mut streams = Vec::new();
        for block in data.chunks(8) {
            let n = block.len() / 4;
            let shuffled: Vec<u8> = (0..block.len())
                .map(|i| block[(i % n) * 4 + i / n])
                .collect();
            streams.push(lz4_flex::block::compress(&shuffled));
        }
        let mut offsets = Vec::new();
        let mut body = Vec::new();
        let base = HEADER_LEN + 4 * streams.len();
        for s in &streams {
            offsets.extend_from_slice(&((base + body.len()) as i32).to_le_bytes());
            body.extend_from_slice(&(s.len() as i32).to_le_bytes());
            body.extend_from_slice(s);
        }
        let total = (base + body.len()) as u32;
        let mut buf = header(FLAG_SHUFFLE | (CODEC_LZ4 << 5), 4, 20, 8, total);
        buf.extend(offsets);
        buf.extend(body);
        assert_eq!(decompress(&buf, 20).unwrap(), data);
    }

    #[test]
    fn other_codecs_are_named() {
        let buf = header(3 << 5, 4, 8, 8, 16);
        let err = decompress(&buf, 8).unwrap_err();
        assert!(err.contains("'zlib'"), "{err}");
    }
}
