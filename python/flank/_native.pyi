"""Type stubs of the extension module flank._native (python/src/lib.rs):
the binding over flank::api that the functions of `flank` call. Results
come back as JSON text (the serialization of summary.json) for flank's
result classes to wrap."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

#: a progress callback: (task, done, total), see flank::progress
Progress = Callable[[str, int, int], None]

__version__: str
SCHEMA_VERSION: int

class FlankError(Exception):
    """An error of flank: `kind` (the FlankError variant: Parse, Model,
    Io, Solver, Memory, …) and `message`."""

    kind: str
    message: str

class SceneError(FlankError):
    """A malformed or refused input file: `file`, `line` (1-based) and
    `key` (the dotted scene key or override, where the error names one)."""

    file: str
    line: int
    key: Optional[str]

class Scene:
    """A validated scene of any pair kind, with its source and overrides."""

    @staticmethod
    def load(path: str, overrides: Optional[Dict[str, Any]] = None) -> "Scene": ...
    @staticmethod
    def from_string(text: str, path: str = "<string>.toml", overrides: Optional[Dict[str, Any]] = None) -> "Scene": ...
    def set(self, key: str, value: Any) -> None:
        """Sets a dotted key (file units, e.g. `load.torque_nm`) and
        validates again; SceneError (with `key`) leaves the scene as it was."""
    def get(self, key: str) -> Any:
        """The value at a dotted key (KeyError if absent)."""
    def to_toml(self) -> str:
        """The scene's TOML with the overrides set."""
    def copy(self) -> "Scene": ...
    @property
    def path(self) -> str: ...
    @property
    def kind(self) -> str:
        """`spur`, `helical`, `spiral_bevel` or `hypoid`."""
    @property
    def overrides(self) -> Dict[str, Any]: ...

def check(scene: Scene) -> str: ...
def tca(
    scene: Scene,
    out: str,
    *,
    approach_mm: float = 0.00635,
    positions_per_pitch: int = 30,
    search_directions: int = 18,
    offset_error_mm: float = 0.0,
    pinion_axial_mm: float = 0.0,
    gear_axial_mm: float = 0.0,
    shaft_angle_error_deg: float = 0.0,
    sweep_mm: Optional[float] = None,
    quiet: bool = False,
) -> Tuple[str, List[str]]: ...
def ltca(
    scene: Scene,
    out: str,
    *,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    roll_angles: Optional[Sequence[float]] = None,
    points_per_line: Optional[int] = None,
    solver: Optional[str] = None,
    local: Optional[str] = None,
    fe_cell_factor: Optional[float] = None,
    cache: Optional[str] = None,
    no_condition: bool = False,
    threads: int = 0,
    span_approach_mm: Optional[float] = None,
    friction_mu: Optional[float] = None,
    increments: Optional[int] = None,
    cross_check: bool = False,
    friction_model: Optional[str] = None,
    edges: Optional[str] = None,
    flank_region: Optional[str] = None,
    compression: Optional[str] = None,
    torques: Optional[Sequence[float]] = None,
    quiet: bool = False,
    progress: Optional[Progress] = None,
) -> str: ...
def fe_run(
    scene: Scene,
    out: str,
    *,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    roll_angles: Optional[Sequence[float]] = None,
    reference_angles: Optional[Sequence[float]] = None,
    law: Optional[str] = None,
    penalty_factor: Optional[float] = None,
    slave: Optional[str] = None,
    friction_mu: Optional[float] = None,
    no_vtu: bool = False,
    decks: bool = False,
    no_refine: bool = False,
    threads: int = 0,
    resume: bool = False,
    quiet: bool = False,
    progress: Optional[Progress] = None,
) -> str: ...
def compare(
    scene: Scene,
    out: str,
    *,
    points_per_line: Sequence[int] = ...,
    fe_flank_sizes: Sequence[float] = ...,
    fe_base_size: Optional[float] = None,
    roll_angles: Optional[Sequence[float]] = None,
    roll_step: float = 1.0,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    local: Optional[str] = None,
    threads: int = 0,
    friction_mu: Optional[float] = None,
    increments: Optional[int] = None,
    friction_model: Optional[str] = None,
    compression: Optional[str] = None,
    pmax_reference: Sequence[str] = ...,
    quiet: bool = False,
    progress: Optional[Progress] = None,
) -> str: ...
def compliance(
    scene: Scene,
    out: str,
    *,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    bodies: Sequence[str] = ...,
    method: Optional[str] = None,
    flanks: Optional[str] = None,
    flank_region: Optional[str] = None,
    clamp_cuts: bool = False,
    threads: int = 0,
    memory_budget_mb: Optional[float] = None,
    block_size: int = 0,
    cache: Optional[str] = None,
    format: Optional[str] = None,
    no_condition: bool = False,
    no_load: bool = False,
) -> str: ...
def read_compliance_tensor(path: str) -> Dict[str, Any]:
    """meta (JSON), sets, labels, set_of, uv (N×2), positions, normals
    (N×3), matrix (3N×3N, mm/N, the file's buffer without a copy)."""
def campaign(
    path: str,
    exe: str,
    *,
    out: Optional[str] = None,
    workers: Optional[int] = None,
    memory_mb: Optional[float] = None,
    quiet: bool = False,
    progress: Optional[Progress] = None,
) -> str: ...
def campaign_collect(path: str, *, out: Optional[str] = None) -> str: ...
def blank(inputs: str) -> str:
    """The ISO 23509 blank outputs (JSON) of an input set (JSON, Annex F names)."""
def grid_convergence(h: Sequence[float], phi: Sequence[float], fs: float = 1.25) -> str: ...
