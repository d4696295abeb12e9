#!/usr/bin/env bash
# Run every fuzz target for a fixed number of inputs from the committed corpus, with a fixed
# seed, so that a run that passes on one machine passes on another (CI calls this). Needs
# `cargo-fuzz` and a nightly toolchain. For a longer, open-ended run of one target:
#   cargo +nightly fuzz run -O gltf fuzz/corpus/gltf -- -max_total_time=3600
set -euo pipefail
cd "$(dirname "$0")/.."
for spec in "scene_toml 30000" "mesh_files 30000" "gltf 5000" "saved_state 50000" \
  "job_manifest 30000" "job_part 50000" \
  "texture_png 30000" "texture_jpeg 30000" "environment_hdr 30000" "image_exr 30000" \
  "vdb_grid 30000"; do
  set -- $spec
  work=$(mktemp -d)
  cp -r "fuzz/corpus/$1/." "$work/"
  log="$work.log"
  start=$(date +%s)
  status=0
  cargo +nightly fuzz run -O "$1" "$work" -- -runs="$2" -seed=1 -rss_limit_mb=2048 -timeout=10 \
    >"$log" 2>&1 || status=$?
  grep -E "^Done|ERROR|panicked|SUMMARY" "$log" || true
  echo "fuzz: $1: $2 runs in $(( $(date +%s) - start )) s, exit $status"
  [ "$status" -eq 0 ] || { tail -40 "$log"; exit "$status"; }
  rm -rf "$work" "$log"
done
