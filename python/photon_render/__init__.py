"""Photon: a photon-mapping global-illumination renderer.

Every render goes through the library call the ``photon`` command line makes, so the same
scene and settings give the same image, bit for bit::

    import photon_render
    scene = photon_render.load_scene("cornell")   # or a .toml, .gltf or .glb file
    image, aovs = photon_render.render(scene, integrator="path", spp=64)
    image.shape                                    # (512, 512, 3), float32, linear RGB

    for image in photon_render.progressive(scene, passes=16):   # sppm, an image per pass
        ...
    run = photon_render.progressive(scene, time=60, checkpoint="c.checkpoint")
    run = photon_render.resume(scene, "c.checkpoint", passes=200)   # after a crash or kill

    photon_render.job_create("job", "scene.toml", tasks=8, integrator="ppm", passes=64)
    photon_render.job_run("job", 3)                # one task, on any machine sharing the folder
    image, info = photon_render.job_merge("job")   # bit for bit the whole render's image

    maps = photon_render.trace_photons(scene, photons=1_000_000)
    maps.arrays("global")["positions"]             # (N, 3) float32

Errors in scenes and settings raise :class:`PhotonError` with the file, line and column.
Ctrl-C (KeyboardInterrupt) stops a render cleanly.
"""

from ._photon import (
    PhotonError,
    PhotonMaps,
    Progressive,
    Scene,
    __version__,
    load_photons,
    load_scene,
    job_create,
    job_merge,
    job_run,
    progressive,
    render,
    resume,
    trace_photons,
)

__all__ = [
    "PhotonError",
    "PhotonMaps",
    "Progressive",
    "Scene",
    "__version__",
    "load_photons",
    "load_scene",
    "job_create",
    "job_merge",
    "job_run",
    "progressive",
    "render",
    "resume",
    "trace_photons",
]
