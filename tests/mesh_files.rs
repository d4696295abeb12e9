//! Mesh files: OBJ/MTL materials, PLY in all three encodings, unknown formats, and the load
//! speed of a large mesh.

use crate::common;

use photon::description::build::build;
use photon::description::load_mesh_file;
use photon::description::{ColorSpec, EmissionSpec, MaterialSpec};
use photon::material::Material;
use photon::math::{Ray, Rgb, Vec2, Vec3};
use std::path::Path;

#[test]
fn obj_with_mtl_maps_colours_lights_glass_mirrors_and_textures() {
    let dir = common::temp_dir("obj");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl paint\nKd 0.2 0.4 0.6\nillum 2\n\
         newmtl lamp\nKd 0 0 0\nKe 3 2 1\n\
         newmtl glass\nNi 1.7\nillum 7\n\
         newmtl chrome\nKs 0.9 0.9 0.9\nillum 5\n\
         newmtl wood\nKd 0.5 0.5 0.5\nmap_Kd wood.png\n",
    )
    .expect("mtl");
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 128, 0]))
        .save(dir.join("wood.png"))
        .expect("png");
    let mut obj = String::from("mtllib m.mtl\n");
    for k in 0..5 {
        let x = k as f32 * 2.0;
        obj += &format!(
            "v {x} 0 0\nv {} 0 0\nv {} 1 0\nv {x} 1 0\n",
            x + 1.0,
            x + 1.0
        );
    }
    obj += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
    for (k, m) in ["paint", "lamp", "glass", "chrome", "wood"]
        .iter()
        .enumerate()
    {
        let b = 4 * k + 1;
        // Quads, the last one with negative (relative) indices.
        if k == 4 {
            obj += &format!("o part{k}\nusemtl {m}\nf -4/1 -3/2 -2/3 -1/4\n");
        } else {
            obj += &format!(
                "o part{k}\nusemtl {m}\nf {b}/1 {}/2 {}/3 {}/4\n",
                b + 1,
                b + 2,
                b + 3
            );
        }
    }
    std::fs::write(dir.join("m.obj"), obj).expect("obj");
    let file = load_mesh_file(&dir.join("m.obj")).expect("reads");
    assert_eq!(file.parts.len(), 5);
    assert_eq!(file.triangle_count(), 10, "each quad is split in two");
    let spec = |i: usize| file.parts[i].material.clone().expect("material");
    assert_eq!(
        spec(0).spec,
        MaterialSpec::Diffuse {
            albedo: ColorSpec::Constant(Rgb::new(0.2, 0.4, 0.6))
        }
    );
    assert_eq!(
        spec(1).emission,
        Some(EmissionSpec::Radiance {
            radiance: Rgb::new(3.0, 2.0, 1.0),
            two_sided: false,
            texture: None,
            spectrum: None,
        })
    );
    assert!(matches!(spec(2).spec, MaterialSpec::Glass { ior, .. } if (ior - 1.7).abs() < 1e-6));
    assert!(
        matches!(spec(3).spec, MaterialSpec::Mirror { reflectance } if (reflectance.x - 0.9).abs() < 1e-6)
    );
    assert!(
        matches!(&spec(4).spec, MaterialSpec::Diffuse { albedo: ColorSpec::Image { file, .. } } if file.ends_with("wood.png"))
    );
    assert_eq!(file.parts[4].mesh.uvs.len(), 4);

    // In a scene: the file's materials, the lamp part is an area light of radiance Ke.
    let toml = "[camera]\nposition = [5, 0.5, 10]\nlook_at = [5, 0.5, 0]\n[[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\n";
    let desc =
        photon::description::toml_read::read_str(toml, &dir.join("s.toml"), &dir).expect("reads");
    let s = build(&desc).expect("builds");
    let power = s.total_power();
    assert!(
        (power - Rgb::new(3.0, 2.0, 1.0) * std::f32::consts::PI)
            .abs()
            .max_element()
            < 1e-4
    );
    let material_at = |x: f32| {
        let h = s
            .intersect(
                &Ray::new(Vec3::new(x, 0.5, 1.0), Vec3::new(0.0, 0.0, -1.0)),
                f32::INFINITY,
            )
            .expect("hit");
        s.material_at(&h)
    };
    assert!(matches!(material_at(4.5), Material::Dielectric(_)));
    assert!(matches!(material_at(6.5), Material::Mirror(_)));
    match material_at(8.5) {
        // sRGB (255, 128, 0) → linear (1, 0.2158, 0): the texture, not Kd.
        Material::Lambertian(l) => assert!(
            (l.albedo - Rgb::new(1.0, 0.2158, 0.0)).abs().max_element() < 1e-3,
            "{:?}",
            l.albedo
        ),
        other => panic!("{other:?}"),
    }

    // With a material override every part takes it and nothing emits.
    let toml = format!(
        "{toml}material = \"grey\"\n[materials.grey]\ntype = \"diffuse\"\n[[lights]]\ntype = \"point\"\nposition = [0, 0, 1]\npower = 1\n"
    );
    let desc =
        photon::description::toml_read::read_str(&toml, &dir.join("s.toml"), &dir).expect("reads");
    let s = build(&desc).expect("builds");
    assert!(
        (s.total_power().x - 1.0).abs() < 1e-5,
        "only the point light emits"
    );
}

/// One PLY mesh (a quad and a triangle, with normals and UVs) in the given encoding.
fn ply(format: &str) -> Vec<u8> {
    let v: [[f32; 8]; 5] = [
        [0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0],
        [0.5, 2.0, 0.0, 0.0, 0.0, 1.0, 0.5, 1.5],
    ];
    let faces: [&[u32]; 2] = [&[0, 1, 2, 3], &[3, 2, 4]];
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face 2\nproperty list uchar uint vertex_indices\nend_header\n"
    )
    .into_bytes();
    let big = format == "binary_big_endian";
    for row in &v {
        for &x in row {
            match format {
                "ascii" => out.extend(format!("{x} ").into_bytes()),
                _ if big => out.extend(x.to_be_bytes()),
                _ => out.extend(x.to_le_bytes()),
            }
        }
        if format == "ascii" {
            out.push(b'\n');
        }
    }
    for f in faces {
        match format {
            "ascii" => {
                let idx: Vec<String> = f.iter().map(u32::to_string).collect();
                out.extend(format!("{} {}\n", f.len(), idx.join(" ")).into_bytes());
            }
            _ => {
                out.push(f.len() as u8);
                for &i in f {
                    out.extend(if big {
                        i.to_be_bytes()
                    } else {
                        i.to_le_bytes()
                    });
                }
            }
        }
    }
    out
}

#[test]
fn ply_reads_the_same_mesh_in_ascii_and_both_binary_encodings() {
    let dir = common::temp_dir("ply");
    let mut meshes = Vec::new();
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let path = dir.join(format!("{format}.ply"));
        std::fs::write(&path, ply(format)).expect("write");
        let file = load_mesh_file(&path).unwrap_or_else(|e| panic!("{format}: {e}"));
        assert_eq!(file.parts.len(), 1);
        meshes.push(file.parts[0].mesh.clone());
    }
    let m = &meshes[0];
    assert_eq!(
        m.triangles,
        vec![[0, 1, 2], [0, 2, 3], [3, 2, 4]],
        "polygons are fanned"
    );
    assert_eq!(m.normals.len(), 5);
    assert_eq!(m.uvs[4], Vec2::new(0.5, 1.5));
    assert_eq!(meshes[1], *m);
    assert_eq!(meshes[2], *m);
}

#[test]
fn mesh_files_need_a_known_extension() {
    let dir = common::temp_dir("ext");
    std::fs::write(dir.join("x.stl"), "solid x").expect("write");
    let e = load_mesh_file(&dir.join("x.stl"))
        .expect_err("refused")
        .to_string();
    assert!(e.contains("unsupported mesh format"), "{e}");
    assert!(load_mesh_file(Path::new("/nonexistent/x.obj")).is_err());
}

/// Load speed of a large mesh, for the record (`cargo test --release --test integration
/// large_mesh_load_speed -- --ignored --nocapture`): a 2-million-triangle bumpy sphere as binary PLY and as OBJ.
#[test]
#[ignore = "timing run, prints triangles per second"]
fn large_mesh_load_speed() {
    let dir = common::temp_dir("big");
    let n = 1000u32;
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (t, p) = (
                0.01 + (std::f32::consts::PI - 0.02) * i as f32 / (n - 1) as f32,
                std::f32::consts::TAU * j as f32 / (n - 1) as f32,
            );
            let r = 1.0 + 0.05 * (8.0 * t).sin() * (8.0 * p).cos();
            positions.push([r * t.sin() * p.cos(), r * t.cos(), r * t.sin() * p.sin()]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let a = i * n + j;
            faces.push([a, a + n, a + 1]);
            faces.push([a + 1, a + n, a + n + 1]);
        }
    }
    let mut ply = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        positions.len(),
        faces.len()
    )
    .into_bytes();
    positions
        .iter()
        .flatten()
        .for_each(|x| ply.extend(x.to_le_bytes()));
    for f in &faces {
        ply.push(3);
        f.iter().for_each(|i| ply.extend(i.to_le_bytes()));
    }
    std::fs::write(dir.join("big.ply"), ply).expect("ply");
    let mut obj = String::new();
    for p in &positions {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in &faces {
        obj += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    std::fs::write(dir.join("big.obj"), obj).expect("obj");
    for file in ["big.ply", "big.obj"] {
        let start = std::time::Instant::now();
        let mesh = load_mesh_file(&dir.join(file)).expect("loads");
        let read = start.elapsed().as_secs_f64();
        let tris = mesh.triangle_count();
        let toml = format!(
            "[camera]\nposition = [0, 0, 4]\nlook_at = [0, 0, 0]\n[materials.m]\ntype = \"diffuse\"\n[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nmaterial = \"m\"\n"
        );
        let desc = photon::description::toml_read::read_str(&toml, &dir.join("s.toml"), &dir)
            .expect("reads");
        let start = std::time::Instant::now();
        let scene = build(&desc).expect("builds");
        let total = start.elapsed().as_secs_f64();
        println!(
            "{file}: {tris} triangles; parse {read:.2} s = {:.2} M triangles/s; parse + scene + BVH {total:.2} s = {:.2} M triangles/s",
            tris as f64 / read / 1e6,
            tris as f64 / total / 1e6
        );
        assert_eq!(scene.primitive_count(), tris);
    }
}
