//! Streaming images into a running [tev](https://github.com/Tom94/tev), the HDR viewer, over
//! its TCP protocol, as pbrt-v4's `--display-server` does: the image is created once and its
//! pixels sent again as a render goes on.
//!
//! tev's protocol (its `Ipc.cpp`): each packet is its total length in bytes as a little-endian
//! `u32` (the four bytes included), then a one-byte type and the type's fields. Integers and
//! floats are little-endian, booleans one byte, strings UTF-8 ending in a zero byte. Photon
//! sends two kinds:
//! - `CreateImage` (type 4): grab focus, name, width and height (`i32`), the number of channels
//!   (`i32`) and their names;
//! - `UpdateImage` version 3 (type 6): grab focus, name, the number of channels (`i32`), their
//!   names, the tile's x, y, width and height (`i32`), each channel's offset and stride into the
//!   data (`i64`, in floats), then the tile's floats: here R, G, B interleaved, row by row.
//!
//! Updates are cut into tiles of at most [`TILE`] × [`TILE`] pixels (192 KB of floats), as
//! tev's own Python client does, so that no packet is large.

use crate::film::Image;
use std::io::Write;
use std::net::TcpStream;
use std::time::Duration;

/// `CreateImage`'s type byte.
pub const CREATE_IMAGE: u8 = 4;
/// `UpdateImage` version 3's type byte (offsets and strides per channel).
pub const UPDATE_IMAGE_V3: u8 = 6;
/// The largest tile side an update packet carries.
pub const TILE: u32 = 128;
/// The channels Photon sends: linear sRGB, which tev shows through the sRGB curve.
const CHANNELS: [&str; 3] = ["R", "G", "B"];
/// How long connecting and each write may take before tev is taken as gone.
const TIMEOUT: Duration = Duration::from_secs(5);

/// A packet under construction: its length is written when it is finished.
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8) -> Self {
        let mut bytes = vec![0; 4];
        bytes.push(kind);
        Self(bytes)
    }

    fn bool(&mut self, b: bool) -> &mut Self {
        self.0.push(u8::from(b));
        self
    }

    /// A string ends at its first zero byte in tev; names are sent without one inside.
    fn string(&mut self, s: &str) -> &mut Self {
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
        self
    }

    fn i32(&mut self, v: i32) -> &mut Self {
        self.0.extend(v.to_le_bytes());
        self
    }

    fn i64(&mut self, v: i64) -> &mut Self {
        self.0.extend(v.to_le_bytes());
        self
    }

    fn f32(&mut self, v: f32) -> &mut Self {
        self.0.extend(v.to_le_bytes());
        self
    }

    fn finish(mut self) -> Vec<u8> {
        let len = u32::try_from(self.0.len()).unwrap_or(u32::MAX);
        self.0[..4].copy_from_slice(&len.to_le_bytes());
        self.0
    }
}

/// The `CreateImage` packet of an image `name` of `width` × `height` R, G, B pixels.
pub fn create_image(name: &str, width: u32, height: u32) -> Vec<u8> {
    let mut p = Packet::new(CREATE_IMAGE);
    p.bool(true)
        .string(name)
        .i32(side(width))
        .i32(side(height))
        .i32(CHANNELS.len() as i32);
    for c in CHANNELS {
        p.string(c);
    }
    p.finish()
}

/// The `UpdateImage` packets that send all of `image`'s pixels, tile by tile in rows of
/// tiles from the top.
pub fn update_image(name: &str, image: &Image) -> Vec<Vec<u8>> {
    let mut packets = Vec::new();
    for y0 in (0..image.height).step_by(TILE as usize) {
        for x0 in (0..image.width).step_by(TILE as usize) {
            let (w, h) = (TILE.min(image.width - x0), TILE.min(image.height - y0));
            let mut p = Packet::new(UPDATE_IMAGE_V3);
            p.bool(false).string(name).i32(CHANNELS.len() as i32);
            for c in CHANNELS {
                p.string(c);
            }
            p.i32(side(x0)).i32(side(y0)).i32(side(w)).i32(side(h));
            for offset in 0..CHANNELS.len() as i64 {
                p.i64(offset);
            }
            for _ in CHANNELS {
                p.i64(CHANNELS.len() as i64);
            }
            for y in y0..y0 + h {
                for x in x0..x0 + w {
                    let c = image.get(x, y);
                    p.f32(c.x).f32(c.y).f32(c.z);
                }
            }
            packets.push(p.finish());
        }
    }
    packets
}

/// An image's side as tev's `i32` (Photon's images are far smaller than 2³¹).
fn side(n: u32) -> i32 {
    i32::try_from(n).unwrap_or(i32::MAX)
}

/// A connection to tev showing one image.
pub struct Tev {
    stream: Option<TcpStream>,
    address: String,
    name: String,
    created: Option<(u32, u32)>,
}

impl Tev {
    /// Connect to tev at `address` (HOST:PORT; tev listens on 127.0.0.1:14158 by default),
    /// for an image that tev will list as `name`.
    pub fn connect(address: &str, name: &str) -> std::io::Result<Self> {
        use std::net::ToSocketAddrs;
        let mut last = None;
        for a in address.to_socket_addrs()? {
            match TcpStream::connect_timeout(&a, TIMEOUT) {
                Ok(stream) => {
                    stream.set_write_timeout(Some(TIMEOUT))?;
                    stream.set_nodelay(true)?;
                    return Ok(Self {
                        stream: Some(stream),
                        address: address.to_owned(),
                        name: name.to_owned(),
                        created: None,
                    });
                }
                Err(e) => last = Some(e),
            }
        }
        Err(last.unwrap_or_else(|| {
            std::io::Error::new(std::io::ErrorKind::NotFound, "no address to connect to")
        }))
    }

    /// Send `image`, creating it in tev first (again if its size changed). A connection that
    /// fails is dropped: this call returns its error and later ones do nothing, so a render
    /// goes on without its viewer (what tev shows is a view, never what the render keeps).
    pub fn show(&mut self, image: &Image) -> std::io::Result<()> {
        let Some(stream) = self.stream.as_mut() else {
            return Ok(());
        };
        let mut send = || -> std::io::Result<()> {
            if self.created != Some((image.width, image.height)) {
                stream.write_all(&create_image(&self.name, image.width, image.height))?;
                self.created = Some((image.width, image.height));
            }
            for packet in update_image(&self.name, image) {
                stream.write_all(&packet)?;
            }
            stream.flush()
        };
        let sent = send();
        if sent.is_err() {
            self.stream = None;
        }
        sent
    }

    /// The HOST:PORT connected to.
    pub fn address(&self) -> &str {
        &self.address
    }
}
