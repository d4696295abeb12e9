//! `photon render --tev HOST:PORT` as tev sees it: a test server on the loopback interface
//! reads what the renderer sends, decodes it as tev's protocol says (its `Ipc.cpp`: a u32
//! length, a type byte, little-endian fields, zero-terminated strings), and rebuilds the image.

use crate::common;

use common::{assert_usage_error, photon, stderr};
use std::io::Read;
use std::net::TcpListener;
use std::path::Path;

/// A packet's fields, read in order.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        assert!(self.0.len() >= n, "a field runs past the packet's end");
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take(4).try_into().expect("4 bytes"))
    }
    fn i64(&mut self) -> i64 {
        i64::from_le_bytes(self.take(8).try_into().expect("8 bytes"))
    }
    fn f32(&mut self) -> f32 {
        f32::from_le_bytes(self.take(4).try_into().expect("4 bytes"))
    }
    fn string(&mut self) -> String {
        let end = self
            .0
            .iter()
            .position(|&b| b == 0)
            .expect("a zero-terminated string");
        let s = String::from_utf8(self.take(end).to_vec()).expect("UTF-8");
        self.take(1);
        s
    }
}

fn length_prefix(packet: &[u8]) -> Fields<'_> {
    let len = u32::from_le_bytes(packet[..4].try_into().expect("4 bytes"));
    assert_eq!(
        len as usize,
        packet.len(),
        "the length counts the whole packet"
    );
    Fields(&packet[4..])
}

#[test]
fn create_image_is_tevs_layout() {
    let packet = photon::io::tev::create_image("box.exr", 300, 7);
    let mut f = length_prefix(&packet);
    assert_eq!(f.u8(), 4);
    assert_eq!(f.u8(), 1, "grab focus");
    assert_eq!(f.string(), "box.exr");
    assert_eq!((f.i32(), f.i32()), (300, 7));
    assert_eq!(f.i32(), 3);
    assert_eq!([f.string(), f.string(), f.string()], ["R", "G", "B"]);
    assert!(f.0.is_empty(), "nothing after the last field");
}

#[test]
fn update_packets_tile_the_image_once_with_its_pixels() {
    // 300 × 7: three tiles across (128, 128, 44), one down.
    let mut image = photon::film::Image::new(300, 7);
    for y in 0..7 {
        for x in 0..300 {
            image.set(x, y, photon::math::Rgb::new(x as f32, y as f32, -0.5));
        }
    }
    let mut seen = vec![0u32; 300 * 7];
    let packets = photon::io::tev::update_image("a\0b", &image);
    assert_eq!(packets.len(), 3);
    for packet in &packets {
        let mut f = length_prefix(packet);
        assert_eq!(f.u8(), 6);
        assert_eq!(f.u8(), 0, "updates leave the focus");
        assert_eq!(f.string(), "ab", "a zero byte would end the name early");
        assert_eq!(f.i32(), 3);
        assert_eq!([f.string(), f.string(), f.string()], ["R", "G", "B"]);
        let (x0, y0, w, h) = (f.i32(), f.i32(), f.i32(), f.i32());
        assert!(w > 0 && h > 0 && w <= 128 && h <= 128);
        assert_eq!([f.i64(), f.i64(), f.i64()], [0, 1, 2], "offsets");
        assert_eq!([f.i64(), f.i64(), f.i64()], [3, 3, 3], "strides");
        assert_eq!(
            f.0.len(),
            (w * h * 3) as usize * 4,
            "exactly the tile's floats"
        );
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                assert_eq!([f.f32(), f.f32(), f.f32()], [x as f32, y as f32, -0.5]);
                seen[(x + 300 * y) as usize] += 1;
            }
        }
    }
    assert!(seen.iter().all(|&n| n == 1), "every pixel sent once");
}

/// What tev would do with the stream: the images created (name, width, height) and the
/// pixels of the last image as the updates left them (R, G, B), with how many updates came.
#[derive(Default)]
struct Viewer {
    created: Vec<(String, i32, i32)>,
    pixels: Vec<[f32; 3]>,
    updates: usize,
}

fn decode(stream: &[u8]) -> Viewer {
    let mut v = Viewer::default();
    let mut rest = stream;
    while !rest.is_empty() {
        let len = u32::from_le_bytes(rest[..4].try_into().expect("a length")) as usize;
        assert!(len > 5 && len <= rest.len(), "a packet of {len} bytes");
        let mut f = Fields(&rest[4..len]);
        rest = &rest[len..];
        match f.u8() {
            4 => {
                let _focus = f.u8();
                let name = f.string();
                let (w, h) = (f.i32(), f.i32());
                assert_eq!(f.i32(), 3);
                let channels = [f.string(), f.string(), f.string()];
                assert_eq!(channels, ["R", "G", "B"]);
                assert!(f.0.is_empty(), "CreateImage has nothing more");
                v.pixels = vec![[f32::NAN; 3]; (w * h) as usize];
                v.created.push((name, w, h));
            }
            6 => {
                let _focus = f.u8();
                let name = f.string();
                let (created, width, height) = v.created.last().cloned().expect("created first");
                assert_eq!(name, created);
                let n = f.i32() as usize;
                let channels: Vec<String> = (0..n).map(|_| f.string()).collect();
                assert_eq!(channels, ["R", "G", "B"]);
                let (x0, y0, w, h) = (f.i32(), f.i32(), f.i32(), f.i32());
                assert!(x0 >= 0 && y0 >= 0 && x0 + w <= width && y0 + h <= height);
                let offsets: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let strides: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let data: Vec<f32> = (0..f.0.len() / 4).map(|_| f.f32()).collect();
                assert!(f.0.is_empty());
                for y in 0..h {
                    for x in 0..w {
                        let px = (x + w * y) as i64;
                        let value = |c: usize| data[(offsets[c] + px * strides[c]) as usize];
                        v.pixels[((x0 + x) + width * (y0 + y)) as usize] =
                            [value(0), value(1), value(2)];
                    }
                }
                v.updates += 1;
            }
            other => panic!("packet type {other}: Photon sends 4 and 6"),
        }
    }
    v
}

/// Render with `--tev` to a test server; what it received, decoded, and the EXR written.
fn render_to_tev(dir: &Path, args: &[&str]) -> (Viewer, Vec<[f32; 3]>) {
    let listener = TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    let address = listener.local_addr().expect("address").to_string();
    let server = std::thread::spawn(move || {
        let (mut socket, _) = listener.accept().expect("the renderer connects");
        let mut bytes = Vec::new();
        socket
            .read_to_end(&mut bytes)
            .expect("read until it closes");
        bytes
    });
    let mut all = vec![
        "render", "cornell", "-q", "-o", "out.exr", "--tev", &address,
    ];
    all.extend(args);
    let o = photon(&all, dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let viewer = decode(&server.join().expect("server"));
    let image = exr::prelude::read_first_rgba_layer_from_file(
        dir.join("out.exr"),
        |resolution, _| vec![[0.0f32; 3]; resolution.width() * resolution.height()],
        |pixels, position, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[position.x() + 20 * position.y()] = [r, g, b];
        },
    )
    .expect("the EXR");
    (viewer, image.layer_data.channel_data.pixels)
}

#[test]
fn tev_sees_each_pass_and_the_final_image_equals_the_file() {
    let dir = common::temp_dir("tev");
    let size = ["--width", "20", "--height", "12"];
    // A progressive render: the image after the first pass, then at most four a second, and
    // the final one.
    let mut args = vec![
        "--integrator",
        "sppm",
        "--passes",
        "3",
        "--photons-per-pass",
        "2000",
    ];
    args.extend(size);
    let (viewer, file) = render_to_tev(&dir, &args);
    assert_eq!(viewer.created, [("out.exr".to_owned(), 20, 12)]);
    assert!(viewer.updates >= 2, "{} updates", viewer.updates);
    assert_eq!(
        viewer.pixels, file,
        "tev's last image is the file's, bit for bit"
    );
    assert!(file.iter().flatten().any(|&v| v > 0.0));
    // A sample-based render: the final image.
    let mut args = vec!["--integrator", "path", "--spp", "2"];
    args.extend(size);
    let (viewer, file) = render_to_tev(&dir, &args);
    assert_eq!(viewer.created.len(), 1);
    assert_eq!(viewer.updates, 1);
    assert_eq!(viewer.pixels, file);
}

#[test]
fn an_unreachable_tev_is_refused_before_rendering() {
    let dir = common::temp_dir("tev-refused");
    // A port nothing listens on: bound, then closed.
    let port = TcpListener::bind("127.0.0.1:0")
        .expect("a port")
        .local_addr()
        .expect("address")
        .port();
    let address = format!("127.0.0.1:{port}");
    let o = photon(
        &[
            "render", "cornell", "--spp", "1", "-o", "x.exr", "--tev", &address,
        ],
        &dir,
    );
    assert_usage_error(&o, "cannot reach tev");
    assert!(!dir.join("x.exr").exists());
    let o = photon(&["render", "cornell", "--tev", "no-port-here"], &dir);
    assert_usage_error(&o, "tev");
}

#[test]
fn a_viewer_that_goes_away_leaves_the_render_whole() {
    let dir = common::temp_dir("tev-gone");
    let listener = TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    let address = listener.local_addr().expect("address").to_string();
    // The viewer takes the connection and closes it at once.
    let server = std::thread::spawn(move || drop(listener.accept().expect("a connection")));
    let o = photon(
        &[
            "render",
            "cornell",
            "-q",
            "-o",
            "out.exr",
            "--tev",
            &address,
            "--integrator",
            "sppm",
            "--passes",
            "4",
            "--photons-per-pass",
            "2000",
            "--width",
            "64",
            "--height",
            "48",
        ],
        &dir,
    );
    server.join().expect("server");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("out.exr").exists());
    assert!(!stderr(&o).contains("panicked"));
}
