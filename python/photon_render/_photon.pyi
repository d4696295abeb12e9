"""Type stubs of the compiled module (see photon_render/__init__.py for the overview)."""

from os import PathLike
from typing import Iterator, Literal, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class PhotonError(ValueError):
    """A scene, setting or file Photon cannot use; the message names the file, line and
    column where it can."""

class Scene:
    @property
    def name(self) -> str: ...
    @property
    def resolution(self) -> tuple[int, int]: ...
    @property
    def warnings(self) -> list[str]: ...
    def to_toml(self, directory: str | PathLike[str] | None = None) -> str:
        """The scene as a TOML scene file; relative paths are written against `directory`."""

def load_scene(name_or_path: str | PathLike[str]) -> Scene:
    """A built-in scene by name (see `photon scenes`), or a .toml, .gltf or .glb file."""

Image = npt.NDArray[np.float32]

def render(
    scene: Scene,
    *,
    threads: int | None = None,
    integrator: Literal["photon", "direct", "path", "sppm", "ppm", "vcm", "bdpt", "lighttrace"] | None = None,
    width: int | None = None,
    height: int | None = None,
    filter: str | None = None,
    spp: int | None = None,
    seed: int | None = None,
    max_depth: int | None = None,
    light_samples: int | None = None,
    spectral: bool | None = None,
    max_radiance: float | None = None,
    photons: int | None = None,
    caustic_photons: int | None = None,
    radius: float | None = None,
    k: int | None = None,
    kernel: Literal["box", "cone", "gaussian", "epanechnikov"] | None = None,
    gather: Literal["final", "none"] | None = None,
    gather_rays: int | None = None,
    indirect_scale: float | None = None,
    per_channel: bool | None = None,
    absorption: float | None = None,
    passes: int | None = None,
    time: float | None = None,
    photons_per_pass: int | None = None,
    alpha: float | None = None,
    sample_range: tuple[int, int] | None = None,
    pass_range: tuple[int, int] | None = None,
) -> tuple[Image, dict[str, Image]]:
    """Render as `photon render` would: (image (H, W, 3) float32 linear RGB, AOVs). Each
    keyword is a render setting (README: render settings); `None` takes the scene's
    `[render]` value or the default. A setting the integrator does not take is an error."""

class Progressive(Iterator[Image]):
    @property
    def passes(self) -> int:
        """Passes done so far, counting those of the checkpoint a resumed run began from."""
    def image(self) -> Image:
        """The image of the passes done so far."""
    def __iter__(self) -> Progressive: ...
    def __next__(self) -> Image: ...

def progressive(
    scene: Scene,
    *,
    threads: int | None = None,
    checkpoint: str | PathLike[str] | None = None,
    checkpoint_every: float = 30.0,
    keep_checkpoint: bool = False,
    **options: object,
) -> Progressive:
    """An sppm (default) or ppm render as an iterator of images, one after each pass; the
    options are `render`'s (give `passes` or `time`, counted from the first pass, which
    always runs). With `checkpoint`, the state is saved there after the first pass, every
    `checkpoint_every` seconds and on KeyboardInterrupt, and removed when the budget is
    spent unless `keep_checkpoint`. A KeyboardInterrupt abandons the pass in flight; the
    completed passes stay, and iterating again continues from them."""

def resume(
    scene: Scene,
    checkpoint: str | PathLike[str],
    *,
    passes: int | None = None,
    time: float | None = None,
    threads: int | None = None,
    checkpoint_every: float = 30.0,
) -> Progressive:
    """Go on from a checkpoint of `scene` (refused for another scene) to `passes` (a pass
    number; the run's own target if neither is given) or for `time` seconds; the images are
    bit-identical to an uninterrupted run's. The checkpoint is kept and updated."""

class PhotonArrays(TypedDict):
    positions: npt.NDArray[np.float32]
    directions: npt.NDArray[np.float32]
    power: npt.NDArray[np.float32]
    normals: npt.NDArray[np.float32]
    depth: npt.NDArray[np.uint8]

class PhotonMaps:
    @property
    def counts(self) -> tuple[int, int]:
        """(global photons, caustic photons)."""
    def arrays(self, kind: Literal["global", "caustic"] = "global") -> PhotonArrays: ...
    def save(self, path: str | PathLike[str]) -> None:
        """Write a .phm file (`photon render --photon-map` reads it)."""
    def __len__(self) -> int: ...

def trace_photons(
    scene: Scene,
    *,
    photons: int | None = 250000,
    caustic_photons: int | None = None,
    seed: int | None = 0,
    per_channel: bool = False,
    threads: int | None = None,
) -> PhotonMaps: ...
def load_photons(path: str | PathLike[str]) -> PhotonMaps: ...

def job_create(
    folder: str | PathLike[str], scene: str | PathLike[str], *, tasks: int, **options: object
) -> int:
    """Write a job folder as `photon job create` does: the scene (a built-in's name or a
    file) with every file it reads, the settings (`render`'s keywords), and the ranges of
    `tasks` tasks (passes for ppm, samples per pixel for path, direct and photon). Returns the
    number of tasks."""

def job_run(
    folder: str | PathLike[str], task: int, *, threads: int | None = None
) -> Literal["rendered", "already done", "done by another worker", "busy"]:
    """Render one task into `folder/parts/TASK.part`, as `photon job run` does."""

class JobInfo(TypedDict):
    done: int
    tasks: int
    units: int
    total: int
    missing: list[int]
    problems: list[str]

def job_merge(folder: str | PathLike[str]) -> tuple[Image, JobInfo]:
    """Merge the parts present; with every task done, the image of one uninterrupted render,
    bit for bit."""
