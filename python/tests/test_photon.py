"""The Python module against the command line: the same image bit for bit, located errors,
AOVs, progressive iteration, photon maps as NumPy arrays, and clean interruption."""

import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import photon_render

ROOT = Path(__file__).resolve().parents[2]

SCENE = """
[camera]
position = [0.0, 1.0, 4.0]
look_at = [0.0, 0.5, 0.0]
resolution = [32, 24]
[materials.white]
type = "diffuse"
albedo = [0.8, 0.8, 0.8]
[materials.glass]
type = "glass"
[[shapes]]
type = "quad"
vertices = [[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2]]
material = "white"
[[shapes]]
type = "sphere"
center = [0.0, 0.6, 0.0]
radius = 0.5
material = "glass"
[[lights]]
type = "point"
position = [0.5, 2.5, 1.0]
power = 100.0
"""


def photon_cli() -> str:
    """The `photon` binary: $PHOTON_CLI, else the repository's release or debug build."""
    env = os.environ.get("PHOTON_CLI")
    if env:
        return env
    for profile in ("release", "debug"):
        p = ROOT / "target" / profile / "photon"
        if p.exists():
            return str(p)
    found = shutil.which("photon")
    if found is None:
        pytest.skip("no photon binary: build it with cargo build --release")
    return found


def read_pfm(path: Path) -> np.ndarray:
    """A PFM image as (H, W, 3) float32, top row first."""
    data = path.read_bytes()
    header, rest = data.split(b"\n", 1)
    assert header == b"PF"
    dims, rest = rest.split(b"\n", 1)
    w, h = map(int, dims.split())
    scale, rest = rest.split(b"\n", 1)
    dtype = "<f4" if float(scale) < 0 else ">f4"
    pixels = np.frombuffer(rest, dtype=dtype, count=w * h * 3).reshape(h, w, 3)
    return pixels[::-1].astype(np.float32)


@pytest.fixture()
def scene_file(tmp_path: Path) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(SCENE)
    return path


@pytest.mark.parametrize(
    "options, flags",
    [
        ({"integrator": "path", "spp": 8}, ["--integrator", "path", "--spp", "8"]),
        (
            {"integrator": "photon", "spp": 2, "photons": 20000, "caustic_photons": 20000},
            ["--spp", "2", "--photons", "20000", "--caustic-photons", "20000"],
        ),
        (
            {"integrator": "sppm", "passes": 3, "photons_per_pass": 5000},
            ["--integrator", "sppm", "--passes", "3", "--photons-per-pass", "5000"],
        ),
    ],
)
def test_render_equals_the_command_line_bit_for_bit(scene_file, tmp_path, options, flags):
    out = tmp_path / "cli.pfm"
    subprocess.run(
        [photon_cli(), "render", str(scene_file), "-q", "-o", str(out), *flags],
        check=True,
        capture_output=True,
    )
    image, aovs = photon_render.render(photon_render.load_scene(scene_file), **options)
    assert image.dtype == np.float32 and image.shape == (24, 32, 3)
    cli = read_pfm(out)
    assert np.array_equal(image, cli), f"max difference {np.abs(image - cli).max()}"
    assert image.mean() > 0


def test_aovs_and_threads(scene_file):
    scene = photon_render.load_scene(scene_file)
    one, aovs = photon_render.render(scene, integrator="photon", spp=2, photons=20000, threads=1)
    two, _ = photon_render.render(scene, integrator="photon", spp=2, photons=20000, threads=2)
    assert np.array_equal(one, two), "the image must not depend on the thread count"
    assert set(aovs) == {"direct", "caustic", "indirect", "albedo", "normal"}
    # The photon integrator's beauty is the sum of its three parts.
    total = aovs["direct"] + aovs["caustic"] + aovs["indirect"]
    assert np.allclose(total, one, rtol=1e-5, atol=1e-6)
    # The floor's albedo is 0.8 where the camera sees it directly (the bottom row straddles
    # its front edge).
    assert np.isclose(aovs["albedo"][-3, 0], 0.8).all()


def test_errors_are_photon_errors_with_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nradus = 2\n")
    with pytest.raises(photon_render.PhotonError, match=r"bad\.toml:4:1: unknown key 'radus'"):
        photon_render.load_scene(bad)
    scene = photon_render.load_scene("cornell")
    with pytest.raises(photon_render.PhotonError, match="'spp2' is not a render setting"):
        photon_render.render(scene, spp2=4)
    with pytest.raises(photon_render.PhotonError, match="a progressive render needs a number of passes or a time"):
        photon_render.render(scene, integrator="sppm")
    assert issubclass(photon_render.PhotonError, ValueError)


def test_progressive_yields_an_image_per_pass_ending_at_the_single_render(scene_file):
    scene = photon_render.load_scene(scene_file)
    options = dict(integrator="ppm", passes=4, photons_per_pass=5000)
    images = list(photon_render.progressive(scene, **options))
    assert len(images) == 4
    final, _ = photon_render.render(scene, **options)
    assert np.array_equal(images[-1], final)
    assert not np.array_equal(images[0], images[-1])


def test_photon_maps_as_arrays_and_phm_files(tmp_path):
    scene = photon_render.load_scene("cornell")
    maps = photon_render.trace_photons(scene, photons=20000, caustic_photons=40000)
    n_global, n_caustic = maps.counts
    arrays = maps.arrays("global")
    assert arrays["positions"].shape == (n_global, 3)
    assert arrays["positions"].dtype == np.float32
    assert arrays["depth"].dtype == np.uint8 and arrays["depth"].shape == (n_global,)
    # Incoming directions and normals are unit vectors; power is positive.
    assert np.allclose(np.linalg.norm(arrays["directions"], axis=1), 1, atol=0.02)
    assert np.allclose(np.linalg.norm(arrays["normals"], axis=1), 1, atol=0.02)
    assert (arrays["power"] >= 0).all() and arrays["power"].sum() > 0
    assert maps.arrays("caustic")["positions"].shape == (n_caustic, 3)
    path = tmp_path / "m.phm"
    maps.save(path)
    again = photon_render.load_photons(path)
    assert again.counts == maps.counts
    assert np.array_equal(again.arrays()["positions"], arrays["positions"])
    out = subprocess.run(
        [photon_cli(), "photons", "info", str(path)], check=True, capture_output=True, text=True
    )
    assert str(n_global) in out.stdout + out.stderr


def test_the_gil_is_released_while_rendering():
    scene = photon_render.load_scene("cornell")
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    photon_render.render(scene, integrator="path", spp=16, width=96, height=96)
    done.set()
    t.join()
    assert ticks > 5, "another Python thread must run while Photon renders"


def test_keyboard_interrupt_cancels_a_render_cleanly():
    import _thread
    import signal

    # A process started in the background of a non-interactive shell inherits SIGINT
    # ignored, and then Python installs no handler and `interrupt_main` does nothing: the
    # render would run its minutes to the end. Install Python's own handler for this test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        scene = photon_render.load_scene("cornell")
        timer = threading.Timer(0.3, _thread.interrupt_main)
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            # Minutes of work if it were not cancelled.
            photon_render.render(scene, integrator="path", spp=4096, width=256, height=256)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    # Photon is still usable afterwards.
    image, _ = photon_render.render(scene, integrator="path", spp=1, width=8, height=8)
    assert image.shape == (8, 8, 3)


def test_scene_to_toml_round_trips(tmp_path):
    scene = photon_render.load_scene("cornell")
    text = scene.to_toml(tmp_path)
    path = tmp_path / "c.toml"
    path.write_text(text)
    again = photon_render.load_scene(path)
    a, _ = photon_render.render(scene, integrator="path", spp=2, width=16, height=16)
    b, _ = photon_render.render(again, integrator="path", spp=2, width=16, height=16)
    assert np.array_equal(a, b)
    assert "cornell" in repr(scene)


def test_keyboard_interrupt_keeps_the_completed_passes():
    import _thread
    import signal

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        scene = photon_render.load_scene("cornell")
        # Passes of seconds each; the interrupt lands in the second one.
        it = photon_render.progressive(
            scene, integrator="sppm", passes=4, width=16, height=16, photons_per_pass=4_000_000
        )
        first = next(it)
        assert it.passes == 1
        timer = threading.Timer(0.3, _thread.interrupt_main)
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            next(it)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    # The pass in flight was abandoned; the completed one is kept, and iterating continues.
    assert it.passes == 1
    assert first.shape == (16, 16, 3)
    second = next(it)
    assert it.passes == 2
    assert second.shape == (16, 16, 3)


@pytest.mark.parametrize(
    "option",
    ["spp", "width", "height", "radius", "time", "alpha", "indirect_scale", "absorption", "k"],
)
@pytest.mark.parametrize("value", [float("nan"), float("inf"), float("-inf")])
def test_non_finite_options_are_refused_by_name(option, value):
    scene = photon_render.load_scene("cornell")
    with pytest.raises(photon_render.PhotonError, match=option):
        options = {"integrator": "path", "spp": 1, "width": 4, "height": 4}
        options[option] = value
        photon_render.render(scene, **options)


@pytest.mark.parametrize("threads", [-1, 2**70, 1.5, 257, True])
def test_bad_thread_counts_are_photon_errors(threads):
    scene = photon_render.load_scene("cornell")
    with pytest.raises(photon_render.PhotonError, match="threads"):
        photon_render.render(scene, integrator="path", spp=1, width=4, height=4, threads=threads)
    with pytest.raises(photon_render.PhotonError, match="threads"):
        photon_render.progressive(scene, passes=1, width=4, height=4, threads=threads)
    with pytest.raises(photon_render.PhotonError, match="threads"):
        photon_render.trace_photons(scene, photons=1000, threads=threads)
    with pytest.raises(photon_render.PhotonError, match="photons"):
        photon_render.trace_photons(scene, photons=-1)


@pytest.mark.parametrize(
    "options",
    [
        {"integrator": "sppm", "passes": 0},
        {"integrator": "ppm", "passes": 0},
        {"integrator": "ppm", "pass_range": (10, 5)},
        {"integrator": "ppm", "pass_range": (5, 5)},
    ],
)
def test_zero_passes_are_refused(options):
    scene = photon_render.load_scene("cornell")
    with pytest.raises(photon_render.PhotonError, match="pass"):
        photon_render.render(scene, width=4, height=4, **options)
    with pytest.raises(photon_render.PhotonError, match="pass"):
        photon_render.progressive(scene, width=4, height=4, **options)


def test_a_time_budget_shorter_than_a_pass_renders_one():
    scene = photon_render.load_scene("cornell")
    options = dict(integrator="sppm", time=1e-9, width=8, height=8, photons_per_pass=1000)
    image, _ = photon_render.render(scene, **options)
    assert image.max() > 0.0
    it = photon_render.progressive(scene, **options)
    assert len(list(it)) == 1
    assert it.passes == 1


def test_a_time_budget_ends_the_iteration():
    scene = photon_render.load_scene("cornell")
    it = photon_render.progressive(
        scene, integrator="sppm", time=0.5, width=8, height=8, photons_per_pass=2000
    )
    for count, _ in enumerate(it, start=1):
        assert count < 1_000_000, "a time budget never ended the iteration"
    assert it.passes == count >= 1
    # Spent, it stays spent.
    assert next(it, None) is None


KILLED_RUN = """
import sys, time, photon_render
scene = photon_render.load_scene(sys.argv[1])
run = photon_render.progressive(scene, checkpoint=sys.argv[2], checkpoint_every=0, **OPTIONS)
for image in run:
    if run.passes == 3:
        print("three passes", flush=True)
        time.sleep(600)   # killed here, in the middle of its run
"""

PROGRESSIVE_OPTIONS = dict(integrator="sppm", passes=30, width=16, height=12, photons_per_pass=20000)


def test_a_checkpointed_run_killed_and_resumed_is_bit_identical(scene_file, tmp_path):
    import signal

    scene = photon_render.load_scene(scene_file)
    whole_run = photon_render.progressive(
        scene, checkpoint=tmp_path / "whole.checkpoint", **PROGRESSIVE_OPTIONS
    )
    whole = list(whole_run)[-1]
    # A finished run removes its checkpoint.
    assert not (tmp_path / "whole.checkpoint").exists()

    checkpoint = tmp_path / "run.checkpoint"
    script = "OPTIONS = " + repr(PROGRESSIVE_OPTIONS) + KILLED_RUN
    child = subprocess.Popen(
        [sys.executable, "-c", script, str(scene_file), str(checkpoint)],
        stdout=subprocess.PIPE,
        text=True,
    )
    assert child.stdout.readline().strip() == "three passes"
    child.send_signal(signal.SIGKILL)
    child.wait()
    assert checkpoint.exists()

    resumed_run = photon_render.resume(scene, checkpoint)
    assert resumed_run.passes == 3
    resumed = list(resumed_run)[-1]
    assert resumed_run.passes == PROGRESSIVE_OPTIONS["passes"]
    assert np.array_equal(resumed, whole)
    # The checkpoint was the run's input: it stays.
    assert checkpoint.exists()


def test_a_checkpoint_is_never_replaced_and_resume_refuses_another_scene(scene_file, tmp_path):
    scene = photon_render.load_scene(scene_file)
    checkpoint = tmp_path / "kept.checkpoint"
    run = photon_render.progressive(
        scene, checkpoint=checkpoint, keep_checkpoint=True, passes=1, width=4, height=4,
        photons_per_pass=1000,
    )
    list(run)
    assert checkpoint.exists()
    before = checkpoint.read_bytes()
    with pytest.raises(photon_render.PhotonError, match="exists: continue it"):
        photon_render.progressive(scene, checkpoint=checkpoint, passes=1, width=4, height=4)
    assert checkpoint.read_bytes() == before
    with pytest.raises(photon_render.PhotonError, match="another scene"):
        photon_render.resume(photon_render.load_scene("cornell"), checkpoint, passes=2)


def test_a_setting_the_integrator_does_not_take_is_refused_by_name():
    scene = photon_render.load_scene("cornell")
    with pytest.raises(photon_render.PhotonError, match=r"photons=1000: the path integrator does not take it"):
        photon_render.render(scene, integrator="path", photons=1000, width=4, height=4)
    with pytest.raises(photon_render.PhotonError, match="not a render setting"):
        photon_render.render(scene, integrator="path", spp=1, bogus=1)
    # A switch given as off asks for nothing, whichever integrator runs.
    photon_render.render(scene, integrator="path", spp=1, width=4, height=4, per_channel=False)


def test_a_python_resume_keeps_what_the_command_line_run_recorded(tmp_path):
    """The checkpoint keeps the run's output and exposure, so the command line can go on
    after Python did, without -o."""
    cli = photon_cli()
    base = ["render", "cornell", "--integrator", "sppm", "--photons-per-pass", "2000",
            "--width", "8", "--height", "8", "-q", "-o", "c.exr", "--exposure", "1"]
    run = subprocess.run([cli, *base, "--passes", "2", "--keep-checkpoint"], cwd=tmp_path,
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    scene = photon_render.load_scene("cornell")
    resumed = photon_render.resume(scene, tmp_path / "c.checkpoint", passes=3)
    assert len(list(resumed)) == 1
    again = subprocess.run([cli, "render", "--resume", "c.checkpoint", "--passes", "4", "-q"],
                           cwd=tmp_path, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    assert (tmp_path / "c.exr").exists()


@pytest.mark.parametrize(
    "options",
    [
        dict(integrator="path", spp=6),
        dict(integrator="ppm", passes=5, photons_per_pass=5000),
    ],
)
def test_a_job_made_run_and_merged_from_python_is_the_whole_render(scene_file, tmp_path, options):
    job = tmp_path / "job"
    tasks = photon_render.job_create(job, scene_file, tasks=3, **options)
    assert tasks == 3
    assert sorted((job / "scene").iterdir())
    # A part of some tasks merges to what they hold.
    assert photon_render.job_run(job, 2, threads=1) == "rendered"
    _, info = photon_render.job_merge(job)
    assert info["done"] == 1 and info["missing"] == [0, 1]
    for task in (1, 0):
        assert photon_render.job_run(job, task) == "rendered"
    assert photon_render.job_run(job, 0) == "already done"
    image, info = photon_render.job_merge(job)
    assert info["done"] == info["tasks"] == 3 and info["missing"] == []
    assert info["units"] == info["total"]
    scene = photon_render.load_scene(scene_file)
    if options["integrator"] == "ppm":
        whole = list(photon_render.progressive(scene, **options))[-1]
    else:
        whole, _ = photon_render.render(scene, **options)
    assert np.array_equal(image, whole)


def test_a_job_refuses_what_cannot_be_split(scene_file, tmp_path):
    with pytest.raises(photon_render.PhotonError, match="sppm cannot be split"):
        photon_render.job_create(tmp_path / "a", scene_file, tasks=2, integrator="sppm", passes=4)
    with pytest.raises(photon_render.PhotonError, match="time=5"):
        photon_render.job_create(tmp_path / "b", scene_file, tasks=2, integrator="ppm", time=5)
