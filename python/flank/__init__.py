"""flank from Python: gear tooth contact (FE contact and compliance-matrix
LTCA) over the Rust library's façade ``flank::api``.

Read a scene, override its keys, run an analysis, read its result::

    import flank
    scene = flank.load_scene("papers/seed002-spur/scene.toml")
    scene.set("load.torque_nm", 104.0)          # validated as the file is
    r = flank.ltca(scene, flank_size=1.5, base_size=3, points_per_line=10)
    r.te_peak_to_peak_urad                      # a summary key as an attribute
    r.cycle                                     # ltca_cycle.csv as a DataFrame
    r.save("out/seed002_ltca")                  # the files `flank ltca` writes

Every analysis takes the options of its command (``flank ltca --help``) as
keyword arguments, with ``-`` written ``_`` (``--flank-size`` is
``flank_size``); an option left ``None`` falls back to the scene's
``[analyses.*]`` key, else to the CLI's default. Without ``out=`` the files
go to a temporary folder that lives as long as the result.

Long calls release the GIL; Ctrl-C raises ``KeyboardInterrupt`` (runs that
poll the stop flag, ``flank run`` between positions and ``flank ltca``
between positions, stop at that safe point; files are written whole or
not at all). ``ltca``, ``fe_run``, ``compare`` and ``campaign`` report
progress (``progress=``: a callable ``(task, done, total)``; by default
tqdm bars when tqdm is installed and ``quiet`` is false; ``False``: none);
an exception raised by the callback stops the run as Ctrl-C does.

Errors: :class:`SceneError` (file, line, key) for a bad scene or
override, :class:`FlankError` (``kind``, ``message``) for the rest.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, Mapping, Optional, Sequence, Union

from . import _native
from ._native import Scene
from ._progress import ProgressCallback, resolve as _progress
from ._results import (
    CampaignResult,
    CheckResult,
    CompareResult,
    ComplianceResult,
    ComplianceTensor,
    FeResult,
    LtcaResult,
    Result,
    TcaResult,
    output_folder,
    read_table,
)

__version__: str = _native.__version__
#: the ``schema_version`` of every ``summary.json`` this build writes
SCHEMA_VERSION: int = _native.SCHEMA_VERSION

FlankError = _native.FlankError
SceneError = _native.SceneError

__all__ = [
    "__version__",
    "SCHEMA_VERSION",
    "FlankError",
    "SceneError",
    "Scene",
    "load_scene",
    "scene_from_string",
    "check",
    "tca",
    "ltca",
    "fe_run",
    "compare",
    "compliance",
    "read_compliance_tensor",
    "campaign",
    "campaign_collect",
    "blank",
    "grid_convergence",
    "ProgressCallback",
    "read_table",
    "Result",
    "CheckResult",
    "TcaResult",
    "LtcaResult",
    "FeResult",
    "CompareResult",
    "ComplianceResult",
    "ComplianceTensor",
    "CampaignResult",
]

PathLike = os.PathLike[str] | str


def load_scene(path: os.PathLike[str] | str, overrides: Optional[Dict[str, Any]] = None) -> Scene:
    """Reads and validates the scene file ``path`` (TOML, any pair kind).

    ``overrides``: dotted keys set before validation (``{"load.torque_nm":
    104.0, "pinion.micro.tip_relief_um": 12}``), with the same checks and
    errors as the file (``flank::api::load_scene_with``). A bad key raises
    :class:`SceneError` with ``file``, ``line`` and ``key``.
    """
    return Scene.load(os.fspath(path), overrides)


def scene_from_string(
    text: str, path: os.PathLike[str] | str = "<string>.toml", overrides: Optional[Dict[str, Any]] = None
) -> Scene:
    """Parses and validates scene TOML text; ``path`` names it in errors and
    anchors its relative paths (measured profiles, included files)."""
    return Scene.from_string(text, os.fspath(path), overrides)


def _scene(scene) -> Scene:
    if isinstance(scene, Scene):
        return scene
    return load_scene(scene)


def _floats(x: Optional[Sequence[float]]):
    return None if x is None else [float(v) for v in x]


def check(scene) -> CheckResult:
    """``flank check``: the pair report of the scene (a :class:`Scene` or a
    path). Cylindrical pairs: ``contact_ratio`` (ε_α), ``overlap_ratio``
    (ε_β), ``working_pressure_angle_deg``, per member geometry,
    ``iso6336_stiffness_n_per_mm_um`` (N/(mm·µm)); bevel/hypoid: the ISO
    23509 blank, cutters and machine settings (mm, degrees)."""
    return CheckResult(json.loads(_native.check(_scene(scene))), None)


def tca(
    scene,
    *,
    out: Optional[os.PathLike[str] | str] = None,
    approach_mm: float = 0.00635,
    positions_per_pitch: int = 30,
    search_directions: int = 18,
    offset_error_mm: float = 0.0,
    pinion_axial_mm: float = 0.0,
    gear_axial_mm: float = 0.0,
    shaft_angle_error_deg: float = 0.0,
    sweep_mm: Optional[float] = None,
    quiet: bool = False,
) -> TcaResult:
    """``flank tca``: unloaded TCA over the mesh cycle with and without edge
    contact, any pair kind.

    approach_mm: elastic approach δ of the contact ellipse (mm; 0.00635
    finished teeth, 0.00381 lapped). positions_per_pitch: positions per
    angular pitch. search_directions: planes of the contact-ellipse search
    over 180° (0: off). offset_error_mm ΔE (mm, > 0: axes apart),
    pinion_axial_mm ΔP, gear_axial_mm ΔG (mm), shaft_angle_error_deg ΔΣ
    (degrees). sweep_mm: V–H sweep of ΔE and ΔP over ±sweep_mm (25 runs;
    vh_sweep.csv, vh_chart). Tables: ``with_edges``, ``without_edges``
    (``unloaded_te_urad`` µrad, ``te_arcsec`` arcsec).
    """
    folder, keep = output_folder(out)
    summary, warnings = _native.tca(
        _scene(scene),
        os.fspath(folder),
        approach_mm=approach_mm,
        positions_per_pitch=positions_per_pitch,
        search_directions=search_directions,
        offset_error_mm=offset_error_mm,
        pinion_axial_mm=pinion_axial_mm,
        gear_axial_mm=gear_axial_mm,
        shaft_angle_error_deg=shaft_angle_error_deg,
        sweep_mm=sweep_mm,
        quiet=quiet,
    )
    return TcaResult(json.loads(summary), folder, keep, warnings)


def ltca(
    scene,
    *,
    out: Optional[os.PathLike[str] | str] = None,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    roll_angles: Optional[Sequence[float]] = None,
    points_per_line: Optional[int] = None,
    solver: Optional[str] = None,
    local: Optional[str] = None,
    fe_cell_factor: Optional[float] = None,
    cache: Optional[os.PathLike[str] | str] = None,
    no_condition: bool = False,
    threads: int = 0,
    span_approach_mm: Optional[float] = None,
    friction_mu: Optional[float] = None,
    increments: Optional[int] = None,
    cross_check: bool = False,
    friction_model: Optional[str] = None,
    edges: Optional[str] = None,
    flank_region: Optional[str] = None,
    compression: Optional[str | float] = None,
    torques: Optional[Sequence[float]] = None,
    quiet: bool = False,
    progress: Union[None, bool, ProgressCallback] = None,
) -> LtcaResult:
    """``flank ltca``: compliance-matrix LTCA over the mesh cycle, any pair kind.

    flank_size, base_size: compliance mesh (mm; default m_n/8 flank, m_n/2
    base, or the scene's [mesh]); element: ``hex20`` or ``wedge15``.
    roll_angles: roll angles (deg, flank's convention). points_per_line: K,
    candidate points per contact line (bevel/hypoid: per major axis).
    solver: ``active-set`` or ``clarabel``. local: local contact model
    (``flank ltca --help``). fe_cell_factor: FE cell half-width across the
    line in flank element sizes. cache: campaign cache of tensors (folder).
    no_condition: skip the condition number of F per position. threads: 0 =
    all cores. span_approach_mm: bevel/hypoid candidate axis out to this
    unloaded separation (mm; default 0.04). friction_mu: Coulomb μ (0 =
    frictionless). increments: load increments of the frictional solve
    (default 10). cross_check: Lemke cross-check of every position.
    friction_model: ``incremental``, ``standstill`` or ``sliding``. edges:
    bevel/hypoid ``with``, ``without`` or ``both``. flank_region:
    spur/helical ``active`` (default) or ``full``. compression: ``none`` or
    a relative accuracy ε in (0, 1) for block low-rank tensors. torques:
    pinion torques (N·m) of the map over torque (default the scene's
    ``[analyses.ltca] torques_nm``, else no map).

    Tables: ``cycle`` (ltca_cycle.csv: ``force_pair<k>_n`` N,
    ``share_pair<k>``, ``te_urad`` µrad, ``te_arcsec`` arcsec), ``pairs``
    (ltca_positions.csv), ``points`` (ltca_points.csv, ``pressure_mpa`` MPa).
    """
    folder, keep = output_folder(out)
    summary = _native.ltca(
        _scene(scene),
        os.fspath(folder),
        flank_size=flank_size,
        base_size=base_size,
        element=element,
        roll_angles=_floats(roll_angles),
        points_per_line=points_per_line,
        solver=solver,
        local=local,
        fe_cell_factor=fe_cell_factor,
        cache=None if cache is None else os.fspath(cache),
        no_condition=no_condition,
        threads=threads,
        span_approach_mm=span_approach_mm,
        friction_mu=friction_mu,
        increments=increments,
        cross_check=cross_check,
        friction_model=friction_model,
        edges=edges,
        flank_region=flank_region,
        compression=None if compression is None else str(compression),
        torques=_floats(torques),
        quiet=quiet,
        progress=_progress(progress, quiet),
    )
    return LtcaResult(json.loads(summary), folder, keep)


def fe_run(
    scene,
    *,
    out: Optional[os.PathLike[str] | str] = None,
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
    progress: Union[None, bool, ProgressCallback] = None,
) -> FeResult:
    """``flank run``: quasi-static FE contact over the mesh cycle, any pair kind.

    flank_size, base_size (mm), element: the sector mesh. roll_angles,
    reference_angles: deg. law: ``hard`` or ``penalty`` (penalty_factor ×
    the automatic slope). slave: ``auto``, ``pinion`` or ``gear``.
    friction_mu: Coulomb μ. no_vtu: no VTU files. decks: also write the
    CalculiX decks. no_refine: do not refine the contact limits. resume:
    continue an interrupted run in ``out`` (its checkpoint.json).

    Tables: spur/helical ``cycle`` (mesh_cycle.csv: ``force_pair<k>_n`` N,
    ``share_pair<k>``, ``max_pressure_pair<k>_mpa`` MPa, ``te_urad`` µrad,
    ``te_um`` µm); bevel/hypoid ``positions``, ``contact_pattern``.
    """
    folder, keep = output_folder(out)
    summary = _native.fe_run(
        _scene(scene),
        os.fspath(folder),
        flank_size=flank_size,
        base_size=base_size,
        element=element,
        roll_angles=_floats(roll_angles),
        reference_angles=_floats(reference_angles),
        law=law,
        penalty_factor=penalty_factor,
        slave=slave,
        friction_mu=friction_mu,
        no_vtu=no_vtu,
        decks=decks,
        no_refine=no_refine,
        threads=threads,
        resume=resume,
        quiet=quiet,
        progress=_progress(progress, quiet),
    )
    return FeResult(json.loads(summary), folder, keep)


def compare(
    scene,
    *,
    out: Optional[os.PathLike[str] | str] = None,
    points_per_line: Sequence[int] = (5, 10, 20, 40),
    fe_flank_sizes: Sequence[float] = (1.0, 0.5),
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
    compression: Optional[str | float] = None,
    pmax_reference: Sequence[os.PathLike[str] | str] = (),
    quiet: bool = False,
    progress: Union[None, bool, ProgressCallback] = None,
) -> CompareResult:
    """``flank compare``: the LTCA (each K of ``points_per_line``) against FE
    contact (each flank size of ``fe_flank_sizes``, mm) at the same
    positions (``roll_angles`` deg, else every ``roll_step`` deg).
    flank_size, base_size, element: the LTCA's compliance mesh.
    pmax_reference: contact-band runs (contact_band.json) as the p_max
    reference. Summary: ``load_sharing_rel_err``, ``te_rel_err``,
    ``pmax_rel_err`` (fractions), ``ltca_cycle_s``, ``fe_cycle_s`` (s)."""
    folder, keep = output_folder(out)
    summary = _native.compare(
        _scene(scene),
        os.fspath(folder),
        points_per_line=[int(k) for k in points_per_line],
        fe_flank_sizes=[float(h) for h in fe_flank_sizes],
        fe_base_size=fe_base_size,
        roll_angles=_floats(roll_angles),
        roll_step=roll_step,
        flank_size=flank_size,
        base_size=base_size,
        element=element,
        local=local,
        threads=threads,
        friction_mu=friction_mu,
        increments=increments,
        friction_model=friction_model,
        compression=None if compression is None else str(compression),
        pmax_reference=[os.fspath(p) for p in pmax_reference],
        quiet=quiet,
        progress=_progress(progress, quiet),
    )
    return CompareResult(json.loads(summary), folder, keep)


def compliance(
    scene,
    *,
    out: Optional[os.PathLike[str] | str] = None,
    flank_size: Optional[float] = None,
    base_size: Optional[float] = None,
    element: Optional[str] = None,
    bodies: Sequence[str] = ("pinion", "gear"),
    method: Optional[str] = None,
    flanks: Optional[str] = None,
    flank_region: Optional[str] = None,
    clamp_cuts: bool = False,
    threads: int = 0,
    memory_budget_mb: Optional[float] = None,
    block_size: int = 0,
    cache: Optional[os.PathLike[str] | str] = None,
    format: Optional[str] = None,
    no_condition: bool = False,
    no_load: bool = False,
) -> ComplianceResult:
    """``flank compliance``: the nodal compliance tensors of the scene's bodies.

    method: ``schur`` or ``blocked``. flanks: the flanks carrying tensors
    (``flank compliance --help``). flank_region: ``full`` or ``active``.
    clamp_cuts: clamp the sector cut faces too. memory_budget_mb,
    block_size: the blocked method's right-hand sides. cache: campaign
    cache folder. format: ``hdf5`` (with the feature) or ``native``.
    no_load: decks without the nominal load. ``result.tensor("pinion")``
    reads a tensor back as numpy arrays.
    """
    folder, keep = output_folder(out)
    summary = _native.compliance(
        _scene(scene),
        os.fspath(folder),
        flank_size=flank_size,
        base_size=base_size,
        element=element,
        bodies=list(bodies),
        method=method,
        flanks=flanks,
        flank_region=flank_region,
        clamp_cuts=clamp_cuts,
        threads=threads,
        memory_budget_mb=memory_budget_mb,
        block_size=block_size,
        cache=None if cache is None else os.fspath(cache),
        format=format,
        no_condition=no_condition,
        no_load=no_load,
    )
    return ComplianceResult(json.loads(summary), folder, keep)


def read_compliance_tensor(path: os.PathLike[str] | str) -> ComplianceTensor:
    """Reads a compliance tensor file (``<body>.compliance.bin`` or ``.h5``):
    C (3N × 3N, mm/N) as a numpy array over the buffer read (no copy), the
    flank nodes' positions, normals, u–v, labels and sets."""
    return ComplianceTensor(_native.read_compliance_tensor(os.fspath(path)))


def campaign(
    path: os.PathLike[str] | str,
    *,
    exe: Optional[os.PathLike[str] | str] = None,
    out: Optional[os.PathLike[str] | str] = None,
    workers: Optional[int] = None,
    memory_mb: Optional[float] = None,
    quiet: bool = False,
    progress: Union[None, bool, ProgressCallback] = None,
) -> CampaignResult:
    """``flank campaign run``: runs the campaign file's jobs not done yet (each
    in a child ``flank`` process: ``exe``, default the ``flank`` on PATH),
    then collects ``table.csv``. ``out`` defaults to the campaign's own."""
    import shutil

    if exe is None:
        found = shutil.which("flank")
        if found is None:
            raise FlankError("campaign: no `flank` executable on PATH; pass exe= (target/release/flank)")
        exe = found
    raw = json.loads(
        _native.campaign(
            os.fspath(path),
            os.fspath(exe),
            out=None if out is None else os.fspath(out),
            workers=workers,
            memory_mb=memory_mb,
            quiet=quiet,
            progress=_progress(progress, quiet),
        )
    )
    return CampaignResult(raw, None if out is None else Path(out))


def campaign_collect(
    path: os.PathLike[str] | str, *, out: Optional[os.PathLike[str] | str] = None
) -> CampaignResult:
    """``flank campaign collect``: the table of the campaign's finished jobs
    (a run on this machine or a Slurm submission), nothing run; writes
    ``table.csv``, ``table.parquet`` and the summaries to the output folder
    (``out``, else the campaign's own). Jobs not done are rows with their
    status."""
    raw = json.loads(_native.campaign_collect(os.fspath(path), out=None if out is None else os.fspath(out)))
    return CampaignResult(raw, None if out is None else Path(out))


def blank(inputs: Union[Mapping[str, Any], os.PathLike[str], str]) -> Dict[str, Any]:
    """``flank blank``: the ISO 23509 blank design of a spiral bevel or
    hypoid pair. ``inputs``: the input set as a dict, a JSON file or JSON
    text, with the key names of the standard's Annex F (``method``,
    ``Sigma_deg``, ``a_mm``, ``z1``, ``z2``, ``de2_mm`` or ``dm2_mm``, …).
    Returns the outputs as ``flank blank`` prints them (Annex F names, mm
    and degrees). A missing or bad key raises :class:`FlankError` naming
    it."""
    if isinstance(inputs, Mapping):
        text = json.dumps(dict(inputs))
    elif isinstance(inputs, os.PathLike) or (isinstance(inputs, str) and not inputs.lstrip().startswith("{")):
        text = Path(inputs).read_text(encoding="utf-8")
    else:
        text = inputs
    return json.loads(_native.blank(text))


def grid_convergence(h: Sequence[float], phi: Sequence[float], fs: float = 1.25) -> Dict[str, Any]:
    """Observed order, Richardson extrapolation and GCI from three grids
    (Celik et al. 2008; ``flank::grid_convergence::gci``, what ``flank
    compare`` and campaigns report): cell sizes ``h`` fine → coarse (strictly
    increasing), results ``phi`` on them, safety factor ``fs``. Returns
    ``order``, ``extrapolated``, ``approximate_error``,
    ``extrapolated_error``, ``gci_fine`` (relative), ``oscillatory``,
    ``iterations``; ValueError when no estimate can be made (no change
    between grids, diverging, sizes not increasing)."""
    h3 = [float(x) for x in h]
    p3 = [float(x) for x in phi]
    if len(h3) != 3 or len(p3) != 3:
        raise ValueError("grid_convergence: three sizes and three results")
    return json.loads(_native.grid_convergence(h3, p3, fs))
