"""Type stubs of gnomon (the compiled module is gnomon._gnomon)."""

from os import PathLike
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str
#: Every technique `setup` takes, by name.
TECHNIQUES: list[str]

Vec3 = Union[Sequence[float], npt.NDArray[np.floating]]
ArrayLike = Union[npt.NDArray[np.floating], Sequence[Any]]
# Technique parameters by the command line's names (cascades=4, stable=True, ...).
Param = Union[bool, int, float, str, Sequence[float], None]

class GnomonError(ValueError):
    """Bad input to gnomon: the message names what is wrong, in one line."""

class Camera:
    """A perspective camera looking from `eye` at `target` (fov in degrees, aspect = w / h)."""

    def __init__(
        self,
        eye: Vec3,
        target: Vec3,
        up: Optional[Vec3] = None,
        fov: float = 60.0,
        aspect: float = 16.0 / 9.0,
        near: float = 1.0,
        far: float = 400.0,
    ) -> None: ...
    @property
    def eye(self) -> tuple[float, float, float]: ...
    @property
    def target(self) -> tuple[float, float, float]: ...
    @property
    def up(self) -> tuple[float, float, float]: ...
    @property
    def fov(self) -> float: ...
    @property
    def aspect(self) -> float: ...
    @property
    def near(self) -> float: ...
    @property
    def far(self) -> float: ...

class Sun:
    """A directional light; `direction` is the way its light travels."""

    def __init__(self, direction: Vec3) -> None: ...
    @property
    def direction(self) -> tuple[float, float, float]: ...

class Spot:
    """A spot light: position, direction, cone half-angle in degrees, range."""

    def __init__(self, position: Vec3, direction: Vec3, half_angle: float, range: float) -> None: ...

class Point:
    """A point light: position and range."""

    def __init__(self, position: Vec3, range: float) -> None: ...

Light = Union[Sun, Spot, Point]

class Scene:
    """Caster and receiver boxes (and, loaded, the meshes `render` draws and named views)."""

    def __init__(self, casters: ArrayLike, receivers: ArrayLike) -> None:
        """Boxes as (N, 2, 3) minimum and maximum corners, or (N, 6)."""
    @staticmethod
    def demo() -> Scene: ...
    @staticmethod
    def builtin(name: str) -> Scene: ...
    @staticmethod
    def load(path: Union[str, PathLike[str]], mesh_height: float = 10.0) -> Scene: ...
    def moved(self, casters: ArrayLike, receivers: ArrayLike) -> Scene:
        """The same scene with its boxes moved (same counts, same order); refits, no rebuild."""
    @property
    def casters(self) -> npt.NDArray[np.float64]: ...
    @property
    def receivers(self) -> npt.NDArray[np.float64]: ...
    @property
    def scene_box(self) -> npt.NDArray[np.float64]: ...
    @property
    def name(self) -> str: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def views(self) -> list[str]: ...
    def view(self, name: str, aspect: float = 16.0 / 9.0) -> tuple[Camera, Light]: ...
    def __len__(self) -> int: ...

class Map:
    """One shadow map of a setup."""

    @property
    def clip_from_world(self) -> npt.NDArray[np.float64]:
        """(4, 4), indexed [row, column]: clip = clip_from_world @ [x, y, z, 1]."""
    @property
    def depth_from_world(self) -> npt.NDArray[np.float64]:
        """(4,): depth = depth_from_world @ [x, y, z, 1]."""
    @property
    def resolution(self) -> int: ...
    @property
    def viewport_inset(self) -> Optional[int]: ...
    @property
    def projection(self) -> str: ...
    @property
    def view_depth_range(self) -> Optional[list[float]]: ...
    @property
    def fallbacks(self) -> list[str]: ...
    @property
    def warp_strength(self) -> Optional[float]: ...
    def project(self, points: ArrayLike) -> npt.NDArray[np.float64]: ...

class Setup:
    """A shadow-map setup: maps, selection and diagnostics."""

    @property
    def technique(self) -> str: ...
    @property
    def fallback(self) -> Optional[str]: ...
    @property
    def maps(self) -> list[Map]: ...
    @property
    def selection(self) -> dict[str, Any]: ...
    @property
    def diagnostics(self) -> dict[str, Any]: ...
    def to_json(self) -> str:
        """Exactly what `gnomon setup --json` prints for the same inputs."""
    def __len__(self) -> int: ...

class Analysis:
    """The dp/ds curves of `analyze`."""

    @property
    def z_n(self) -> float: ...
    @property
    def z_f(self) -> float: ...
    @property
    def gamma(self) -> float: ...
    @property
    def resolution(self) -> int: ...
    @property
    def logarithmic_ideal(self) -> float: ...
    @property
    def techniques(self) -> list[str]: ...
    @property
    def rows(self) -> list[dict[str, Any]]: ...
    def curve(self, technique: str) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def to_json(self) -> str: ...

class Frame:
    """A rendered frame."""

    @property
    def frame(self) -> npt.NDArray[np.uint8]:
        """(H, W, 3) sRGB."""
    @property
    def mask(self) -> npt.NDArray[np.uint8]:
        """(H, W): 255 lit, 0 shadowed, 128 no geometry."""
    @property
    def error_map(self) -> Optional[npt.NDArray[np.float32]]:
        """(H, W) pixels per texel (undersampling); None for the volumes."""
    @property
    def setup(self) -> Optional[Setup]: ...
    @property
    def device(self) -> str: ...
    @property
    def timings(self) -> dict[str, float]: ...

def setup(
    technique: str,
    camera: Camera,
    light: Light,
    scene: Scene,
    resolution: int = 2048,
    samples: Optional[tuple[ArrayLike, ArrayLike]] = None,
    **params: Param,
) -> Setup:
    """Shadow-map matrices for `technique` (one of TECHNIQUES); see help(gnomon.setup)."""

def project(map: Map, points: ArrayLike) -> npt.NDArray[np.float64]:
    """(N, 3) world points to the map's NDC; NaN rows where a point has none."""

def analyze(
    zn: float = 1.0,
    zf: float = 100.0,
    gamma: float = 90.0,
    samples: int = 200,
    resolution: int = 2048,
    **params: Param,
) -> Analysis:
    """dp/ds along the view axis of every technique, as `gnomon analyze`."""

def render(
    scene: Scene,
    camera: Camera,
    light: Light,
    technique: str = "focused",
    size: tuple[int, int] = (640, 360),
    resolution: int = 2048,
    **params: Param,
) -> Frame:
    """Render with `technique`'s shadows, or "volumes" for the exact shadows."""

def compare(
    scene: Scene,
    camera: Camera,
    light: Light,
    techniques: Optional[Sequence[str]] = None,
    size: tuple[int, int] = (640, 360),
    resolution: int = 2048,
    **params: Param,
) -> list[dict[str, Any]]:
    """Each technique judged against the exact volumes: gnomon compare --json's rows."""
