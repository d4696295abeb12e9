//! Decoded-image memory. One budget covers every image the process holds decoded: textures
//! (PNG, JPEG, from files or inside glTF), environment maps (OpenEXR, Radiance HDR, PFM) and
//! images read to compare. Each reader asks for its image's bytes from the file's header,
//! before any pixel is decoded, and a file whose pixels would not fit beside what is already
//! held is refused. Decoded textures are kept by content, so one image used by many materials
//! (or files) is decoded once and held once.
//!
//! The budget is [`DEFAULT_LIMIT`], or the environment variable [`LIMIT_VARIABLE`] (bytes,
//! with an optional `K`, `M`, `G` or `T` suffix for powers of 1024).

use crate::error::{Error, Result};
use std::any::Any;
use std::collections::HashMap;
use std::hash::BuildHasher;
use std::path::Path;
use std::sync::{Arc, Mutex, MutexGuard, OnceLock, Weak};

/// The budget when [`LIMIT_VARIABLE`] is not set: 4 GiB, a 16k × 16k RGB texture.
pub const DEFAULT_LIMIT: u64 = 4 << 30;

/// The environment variable that sets the budget.
pub const LIMIT_VARIABLE: &str = "PHOTON_IMAGE_MEMORY";

/// The budget in bytes: [`LIMIT_VARIABLE`] if set, else [`DEFAULT_LIMIT`].
pub fn limit() -> Result<u64> {
    match std::env::var(LIMIT_VARIABLE) {
        Ok(value) => parse_size(&value).ok_or_else(|| {
            Error::InvalidSetting(format!(
                "{LIMIT_VARIABLE}={value:?}: expected a number of bytes, optionally followed by K, M, G or T (powers of 1024)"
            ))
        }),
        Err(_) => Ok(DEFAULT_LIMIT),
    }
}

/// `123`, `512M`, `4G`, … in bytes (binary multiples); `None` if malformed or too large.
fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, shift) = match text.char_indices().last()? {
        (i, 'k' | 'K') => (&text[..i], 10),
        (i, 'm' | 'M') => (&text[..i], 20),
        (i, 'g' | 'G') => (&text[..i], 30),
        (i, 't' | 'T') => (&text[..i], 40),
        _ => (text, 0),
    };
    let n: u64 = digits.trim().parse().ok()?;
    n.checked_mul(1 << shift)
}

/// `1.5 GiB`, `768 KiB`, `12 bytes`.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [(&str, u32); 4] = [("TiB", 40), ("GiB", 30), ("MiB", 20), ("KiB", 10)];
    for (unit, shift) in UNITS {
        if bytes >= 1 << shift {
            let value = bytes as f64 / (1u64 << shift) as f64;
            return format!("{} {unit}", (value * 100.0).round() / 100.0);
        }
    }
    format!("{bytes} bytes")
}

/// What decoding an image of `width` × `height` pixels costs: the bytes per pixel of what it
/// keeps, and of what it needs only while decoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    pub width: u32,
    pub height: u32,
    pub kept_per_pixel: u64,
    pub transient_per_pixel: u64,
}

impl Footprint {
    fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Bytes kept once decoded.
    pub fn kept(&self) -> u64 {
        self.pixels().saturating_mul(self.kept_per_pixel)
    }

    /// Bytes at the peak of decoding.
    pub fn peak(&self) -> u64 {
        self.pixels()
            .saturating_mul(self.kept_per_pixel + self.transient_per_pixel)
    }
}

/// Images held decoded, the decodes under way, and the texture cache.
#[derive(Default)]
struct Ledger {
    /// Bytes asked for by decodes under way.
    pending: u64,
    /// Decoded images and their bytes; each counts while something holds it.
    held: Vec<(u64, Weak<dyn Any + Send + Sync>)>,
    /// Decoded textures by content key.
    cache: HashMap<u64, Weak<dyn Any + Send + Sync>>,
}

impl Ledger {
    fn held_bytes(&mut self) -> u64 {
        self.held.retain(|(_, w)| w.strong_count() > 0);
        self.held.iter().map(|(bytes, _)| bytes).sum()
    }
}

fn ledger() -> MutexGuard<'static, Ledger> {
    static LEDGER: OnceLock<Mutex<Ledger>> = OnceLock::new();
    LEDGER
        .get_or_init(Mutex::default)
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Bytes of decoded images held now.
pub fn held_bytes() -> u64 {
    ledger().held_bytes()
}

/// Room for one image's decode, taken from the budget until dropped (or turned into a held
/// image by [`Reservation::hold`]).
#[must_use = "the room is given back when the reservation is dropped"]
#[derive(Debug)]
pub struct Reservation {
    bytes: u64,
}

impl Reservation {
    /// Count `image` against the budget for as long as it lives, at `bytes`.
    pub fn hold<T: Any + Send + Sync>(self, image: &Arc<T>, bytes: u64) {
        let weak: Weak<dyn Any + Send + Sync> = Arc::downgrade(image) as _;
        ledger().held.push((bytes, weak));
    }
}

impl Drop for Reservation {
    fn drop(&mut self) {
        let mut ledger = ledger();
        ledger.pending = ledger.pending.saturating_sub(self.bytes);
    }
}

/// Take room for decoding the image `path` describes in its header, or refuse it: the peak
/// of its decode, beside what is held and being decoded, must fit the budget.
pub fn reserve(path: &Path, footprint: Footprint) -> Result<Reservation> {
    let limit = limit()?;
    let peak = footprint.peak();
    let mut ledger = ledger();
    let used = ledger.held_bytes() + ledger.pending;
    if used.saturating_add(peak) > limit {
        let (w, h) = (footprint.width, footprint.height);
        let besides = if used > 0 {
            format!(
                " ({} of it already held by other images)",
                format_bytes(used)
            )
        } else {
            String::new()
        };
        return Err(Error::BadImage {
            path: path.to_owned(),
            message: format!(
                "{w}×{h} pixels need {} decoded, more than the {} budget for decoded images{besides}; {LIMIT_VARIABLE} sets the budget",
                format_bytes(peak),
                format_bytes(limit),
            ),
        });
    }
    ledger.pending += peak;
    Ok(Reservation { bytes: peak })
}

/// A key for encoded image bytes and how they are decoded (`kind`): a keyed hash whose key is
/// drawn once per process, so that no file can be made to collide with another on purpose.
pub fn content_key(kind: u8, bytes: &[u8]) -> u64 {
    static KEYS: OnceLock<std::collections::hash_map::RandomState> = OnceLock::new();
    KEYS.get_or_init(Default::default).hash_one((kind, bytes))
}

/// The decoded image of `key`, if one is still held.
pub fn cached<T: Any + Send + Sync>(key: u64) -> Option<Arc<T>> {
    let mut ledger = ledger();
    let found = ledger.cache.get(&key)?.upgrade();
    if found.is_none() {
        ledger.cache.remove(&key);
    }
    found?.downcast::<T>().ok()
}

/// Remember the decoded image of `key` (for as long as something holds it).
pub fn remember<T: Any + Send + Sync>(key: u64, image: &Arc<T>) {
    let weak: Weak<dyn Any + Send + Sync> = Arc::downgrade(image) as _;
    let mut ledger = ledger();
    ledger.cache.retain(|_, w| w.strong_count() > 0);
    ledger.cache.insert(key, weak);
}

/// A zeroed buffer of `len` elements, or an error naming `path` if memory is short (rather than
/// an abort).
pub fn zeroed<T: Clone + Default>(path: &Path, len: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| Error::BadImage {
        path: path.to_owned(),
        message: format!(
            "cannot allocate {} for its pixels",
            format_bytes((len as u64).saturating_mul(size_of::<T>() as u64))
        ),
    })?;
    v.resize(len, T::default());
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size("4G"), Some(4 << 30));
        assert_eq!(parse_size(" 512m "), Some(512 << 20));
        assert_eq!(parse_size("1T"), Some(1 << 40));
        assert_eq!(parse_size("x"), None);
        assert_eq!(parse_size("-1"), None);
        assert_eq!(parse_size("G"), None);
        assert_eq!(parse_size("99999999999T"), None);
        assert_eq!(format_bytes(4 << 30), "4 GiB");
        assert_eq!(format_bytes(1536 << 20), "1.5 GiB");
        assert_eq!(format_bytes(12), "12 bytes");
    }

    #[test]
    fn the_cache_hands_back_only_images_still_held() {
        // Other tests of this binary decode too: compare against the held bytes seen here.
        let image = Arc::new(vec![0u8; 16]);
        let footprint = Footprint {
            width: 4,
            height: 1,
            kept_per_pixel: 4,
            transient_per_pixel: 0,
        };
        let r = reserve(Path::new("x"), footprint).expect("fits");
        r.hold(&image, 16);
        let key = content_key(7, b"abc");
        remember(key, &image);
        let again = cached::<Vec<u8>>(key).expect("still held");
        assert!(Arc::ptr_eq(&again, &image));
        assert!(cached::<String>(key).is_none(), "another type is not a hit");
        drop((image, again));
        assert!(
            cached::<Vec<u8>>(key).is_none(),
            "dropped images leave the cache"
        );
    }
}
