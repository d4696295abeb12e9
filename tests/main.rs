//! The integration tests, as one test binary: one link instead of one per file keeps a
//! clean build's `target/` small (each binary carries the whole library). Every file in
//! `tests/` is a module here, except `bvh.rs`, its own binary so that the Embree build tests
//! only it; `tidy::every_test_file_is_built` checks the list.
//!
//! Run one file's tests by its name: `cargo test --test integration medium::`.

mod common;

mod absorption;
mod bench;
mod bsdf;
mod camera_paths;
mod cli;
mod cli_env;
mod cli_progressive;
mod cli_scenes;
mod cli_validate;
mod decoder_limits;
mod environment;
mod exported_scenes;
mod gltf_blender;
mod gltf_files;
mod gltf_reading;
mod hardening;
mod hardening_run;
mod job_hardening;
mod jobs;
mod kill;
mod large_values;
mod light_transport;
mod lights;
mod materials;
mod max_radiance;
mod media_placement;
mod medium;
mod medium_grid;
mod mesh_files;
mod modeling;
mod photon_render;
mod photons;
mod progressive;
mod render;
mod render_job;
mod sampling_chi2;
mod scene_errors;
mod scene_files;
mod scene_fuzz;
mod seed_layout;
mod settings_everywhere;
mod spectral;
mod tev;
mod tidy;
mod validation;
mod vcm;
mod vdb_files;
mod viewer;
