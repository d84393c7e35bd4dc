# Type stub of the package iaa (its compiled part, iaa._iaa, has no Python source to read).
# docs/python.md describes the API; every function's docstring says the same at run time.
from os import PathLike
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Vec3 = Tuple[float, float, float]
_Progress = Optional[Callable[[str, int, int], None]]
_Overrides = Union[Mapping[str, Any], Sequence[str], None]

class Scene:
    """A scene: surface, bounds, camera, image, material, lights, render settings."""

    def __init__(
        self,
        expression: str,
        bounds: Tuple[Sequence[float], Sequence[float]],
        *,
        params: Optional[Mapping[str, float]] = ...,
        camera: Optional[Mapping[str, Any]] = ...,
        image: Optional[Mapping[str, Any]] = ...,
        material: Optional[Mapping[str, Any]] = ...,
        lights: Optional[Sequence[Mapping[str, Any]]] = ...,
        render: Optional[Mapping[str, Any]] = ...,
        name: str = ...,
    ) -> None: ...
    def with_overrides(self, overrides: _Overrides) -> Scene:
        """A copy with more overrides: {'camera.fov': 30} or ['camera.fov=30'] (as --set)."""
    @property
    def name(self) -> str: ...
    @property
    def expression(self) -> str: ...
    @property
    def params(self) -> dict[str, float]: ...
    @property
    def bounds(self) -> Tuple[_Vec3, _Vec3]:
        """((x0, y0, z0), (x1, y1, z1)): nothing outside exists."""
    @property
    def camera(self) -> dict[str, Any]:
        """{'eye': ..., 'look_at': ..., 'up': ..., 'fov': degrees}"""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def background(self) -> _Vec3: ...
    @property
    def material(self) -> dict[str, Any]: ...
    @property
    def lights(self) -> list[dict[str, _Vec3]]: ...
    @property
    def settings(self) -> dict[str, Any]:
        """The [render] settings, as the render report writes them."""
    @property
    def source(self) -> str:
        """The file's path, or 'iaa.Scene' for a scene built in Python."""
    @property
    def overrides(self) -> list[str]:
        """The overrides applied, as 'key=value' strings."""

def load_scene(path: Union[str, PathLike[str]], overrides: _Overrides = None) -> Scene:
    """Loads a scene file as `iaa render SCENE --set KEY=VALUE ...` does."""

class EvalResult:
    """What iaa.eval found; parts not asked for are None."""

    @property
    def expression(self) -> str: ...
    @property
    def slots(self) -> int: ...
    @property
    def operations(self) -> int: ...
    @property
    def value(self) -> Optional[float]: ...
    @property
    def gradient(self) -> Optional[_Vec3]: ...
    @property
    def interval(self) -> Optional[Tuple[float, float]]: ...
    @property
    def interval_gradient(self) -> Optional[Tuple[Optional[Tuple[float, float]], ...]]: ...
    @property
    def partial_domain(self) -> Optional[bool]: ...
    @property
    def certified_empty(self) -> Optional[bool]: ...

def eval(
    expr: str,
    point: Optional[Sequence[float]] = None,
    box: Optional[Sequence[Any]] = None,
    params: Mapping[str, float] = ...,
) -> EvalResult:
    """f and its gradient at a point; interval f and gradient over a box.

    box: ((x0, x1), (y0, y1), (z0, z1)) or (x0, x1, y0, y1, z0, z1).
    """

class RenderResult:
    """What iaa.render returns; the arrays share the render's memory, rows from the top."""

    @property
    def image(self) -> npt.NDArray[np.uint8]:
        """(H, W, 3): the pixels of the PNG `iaa render -o` writes."""
    @property
    def linear(self) -> npt.NDArray[np.float32]:
        """(H, W, 3): linear RGB."""
    @property
    def certificate(self) -> npt.NDArray[np.uint8]:
        """(H, W): 0 certified empty, 1 certified covered, 2 uncertain, 3 not rendered."""
    @property
    def coverage(self) -> npt.NDArray[np.float32]:
        """(H, W): fraction of each pixel's area shown as surface."""
    @property
    def leaves(self) -> npt.NDArray[np.uint32]:
        """(H, W): IAA leaves (or rays) shaded per pixel."""
    @property
    def evaluations(self) -> npt.NDArray[np.uint32]:
        """(H, W): interval evaluations per pixel."""
    @property
    def report(self) -> dict[str, Any]:
        """The JSON report of `iaa render --report`."""
    def aov_images(self) -> dict[str, npt.NDArray[np.uint8]]:
        """The certificate, coverage, leaves and evals images of `iaa render --aov`."""

def render(
    scene: Scene,
    method: Optional[str] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    *,
    max_level: Optional[int] = None,
    threshold: Optional[float] = None,
    depth_tol: Optional[float] = None,
    adaptive_threshold: Optional[float] = None,
    shadows: Optional[bool] = None,
    window: Union[str, Sequence[int], None] = None,
    threads: int = 0,
    progress: _Progress = None,
) -> RenderResult:
    """Renders a scene as `iaa render` does (method None: the scene's, 'iaa' by default)."""

def write_png(path: Union[str, PathLike[str]], image: npt.ArrayLike) -> None:
    """Writes an (H, W, 3) or (H, W, 4) uint8 image with `iaa render`'s PNG writer."""

class EncloseResult:
    """The enclosure's leaves; every point of the surface in the bounds lies in one of them."""

    @property
    def boxes(self) -> npt.NDArray[np.float64]:
        """(N, 6): x0, x1, y0, y1, z0, z1."""
    @property
    def classes(self) -> npt.NDArray[np.uint8]:
        """(N,): 1 crossing (certified surface), 2 possible."""
    @property
    def depths(self) -> npt.NDArray[np.uint8]: ...
    @property
    def f(self) -> npt.NDArray[np.float64]:
        """(N, 2): an enclosure of f on each leaf."""
    @property
    def report(self) -> dict[str, Any]: ...

def enclose(
    scene: Scene,
    depth: Optional[int] = None,
    *,
    cell_size: Optional[float] = None,
    refine_possible: int = 0,
    max_boxes: int = 20000000,
    threads: int = 0,
    progress: _Progress = None,
) -> EncloseResult:
    """Encloses the surface as `iaa enclose` does (depth None: 7)."""

class MeshResult:
    """A mesh: vertices and faces share its memory; normals point towards increasing f."""

    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """(V, 3)."""
    @property
    def faces(self) -> npt.NDArray[np.int32]:
        """(F, 3) vertex indices."""
    @property
    def report(self) -> dict[str, Any]:
        """The JSON report of `iaa mesh --report`, without its two file keys."""
    def save(self, path: Union[str, PathLike[str]], binary: bool = False) -> None:
        """Writes the file `iaa mesh -o PATH` writes (.ply, .obj, .off, .stl)."""

def mesh(
    scene: Scene,
    method: str = "certified",
    resolution: int = 256,
    *,
    threads: int = 0,
    progress: _Progress = None,
    min_depth: int = ...,
    max_depth: int = ...,
    strict: bool = ...,
    depth: int = ...,
    refine: int = ...,
    flat_tolerance: float = ...,
    max_boxes: int = ...,
    facet_size: float = ...,
    facet_distance: float = ...,
    facet_angle: float = ...,
    grid: int = ...,
) -> MeshResult:
    """Meshes the surface as `iaa mesh` does: certified, octree, cgal or vtk."""

class CompareResult:
    """Per pixel, a mesh's view against the IAA render's certificates."""

    @property
    def lost(self) -> npt.NDArray[np.bool_]:
        """(H, W): IAA certifies surface, the mesh shows none."""
    @property
    def wrong(self) -> npt.NDArray[np.bool_]:
        """(H, W): IAA certifies empty, the mesh shows surface."""
    @property
    def agreement(self) -> npt.NDArray[np.uint8]: ...
    @property
    def diff(self) -> npt.NDArray[np.uint8]:
        """(H, W, 3): the diff picture of `iaa compare -o`."""
    @property
    def report(self) -> dict[str, Any]: ...

def compare(
    scene: Scene,
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    *,
    rays: int = 4,
    threads: int = 0,
    progress: _Progress = None,
) -> CompareResult:
    """Sets a mesh against the render's certificates as `iaa compare` does."""
