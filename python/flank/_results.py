"""Result objects of the analyses: the typed summary (``summary.json``) as a
dict and as attributes, the tables the run wrote (CSV) as pandas
DataFrames, and ``save(folder)`` for the files exactly as the CLI writes
them."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Dict, Iterator, List, Mapping, Optional

__all__ = [
    "Result",
    "CheckResult",
    "TcaResult",
    "LtcaResult",
    "FeResult",
    "CompareResult",
    "ComplianceResult",
    "ComplianceTensor",
    "CampaignResult",
    "read_table",
]


def read_table(path: os.PathLike[str] | str):
    """A CSV file of flank as a pandas DataFrame: the column names as the
    file's header (units in the names: ``force_pair1_n``, ``te_urad``),
    floats read back to the bit (pandas < 3: ``float_precision="round_trip"``)."""
    import pandas as pd

    if int(pd.__version__.split(".")[0]) >= 3:
        # pandas 3 parses floats correctly rounded by default (and deprecates the option)
        return pd.read_csv(path)
    return pd.read_csv(path, float_precision="round_trip")


class Tables(Mapping[str, Any]):
    """The CSV tables of a result folder by file stem (``ltca_cycle`` for
    ``ltca_cycle.csv``), each read into a DataFrame on first access."""

    def __init__(self, folder: Path):
        self._folder = folder
        self._cache: Dict[str, Any] = {}

    def _names(self) -> List[str]:
        return sorted(p.stem for p in self._folder.glob("*.csv"))

    def __getitem__(self, name: str):
        if name not in self._cache:
            path = self._folder / f"{name}.csv"
            if not path.is_file():
                raise KeyError(f"{name}: no {name}.csv in {self._folder} (tables: {', '.join(self._names())})")
            self._cache[name] = read_table(path)
        return self._cache[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())

    def __len__(self) -> int:
        return len(self._names())


class Result:
    """What an analysis returned and wrote.

    * ``summary``: the typed result as a dict (the keys and units of
      ``summary.json``; docs/outputs.md);
    * any summary key as an attribute (``result.te_peak_to_peak_urad``);
    * ``tables``: the run's CSV files as DataFrames by file stem;
    * ``folder``: where the run wrote its files (a temporary folder, removed
      with the result, unless the call was given ``out=``);
    * ``save(folder)``: copies those files, the CLI's files for the same
      command and options.
    """

    def __init__(self, summary: Dict[str, Any], folder: Optional[Path], keep: Any = None):
        self.summary: Dict[str, Any] = summary
        self.folder: Optional[Path] = folder
        # a temporary output folder lives as long as the result
        self._keep = keep
        self.tables: Mapping[str, Any] = Tables(folder) if folder is not None else {}

    def __getattr__(self, name: str) -> Any:
        summary = self.__dict__.get("summary", {})
        if name in summary:
            return summary[name]
        raise AttributeError(f"{type(self).__name__} has no attribute or summary key {name!r}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.summary))

    @property
    def files(self) -> List[Path]:
        """The files the run wrote (relative to ``folder``)."""
        if self.folder is None:
            return []
        return sorted(p.relative_to(self.folder) for p in self.folder.rglob("*") if p.is_file())

    def save(self, folder: os.PathLike[str] | str) -> Path:
        """Copies the files of the run into ``folder`` (created; files of the
        same name replaced): the files ``flank <command> --out folder`` writes."""
        if self.folder is None:
            raise ValueError(f"{type(self).__name__} has no files to save")
        dest = Path(folder)
        dest.mkdir(parents=True, exist_ok=True)
        if dest.resolve() != self.folder.resolve():
            shutil.copytree(self.folder, dest, dirs_exist_ok=True)
        return dest

    def __repr__(self) -> str:
        where = f", folder={str(self.folder)!r}" if self.folder is not None else ""
        return f"{type(self).__name__}({len(self.summary)} summary keys{where})"


class CheckResult(Result):
    """``flank check``: the pair report (contact ratios, working pressure
    angle, ISO 6336 stiffness; bevel/hypoid: ISO 23509 blank and cutting
    reports). No files."""


class TcaResult(Result):
    """``flank tca``: the unloaded TCA with and without edge contact.
    Tables: ``tca_with_edges``, ``tca_without_edges`` (per position and
    tooth pair), bevel/hypoid also ``transitions``."""

    def __init__(self, summary, folder, keep=None, warnings: Optional[List[str]] = None):
        super().__init__(summary, folder, keep)
        #: the trace's iteration limits, crossing flanks (the CLI prints them to stderr)
        self.warnings: List[str] = list(warnings or [])

    @property
    def with_edges(self):
        """``tca_with_edges.csv`` as a DataFrame."""
        return self.tables["tca_with_edges"]

    @property
    def without_edges(self):
        """``tca_without_edges.csv`` as a DataFrame."""
        return self.tables["tca_without_edges"]


class LtcaResult(Result):
    """``flank ltca``: the compliance-matrix LTCA over the mesh cycle
    (``flank::ltca::summary::LtcaResult``).

    Tables: ``cycle`` (``ltca_cycle.csv``, one row per roll angle:
    ``force_pair<k>_n`` N, ``share_pair<k>``, ``te_urad`` µrad at the pinion,
    ``te_arcsec`` arcsec at the gear), ``pairs`` (``ltca_positions.csv``,
    one row per position and tooth pair) and ``points``
    (``ltca_points.csv``, ``pressure_mpa`` MPa per contact point).
    A bevel/hypoid LTCA with and without edges has the two cycles'
    summaries under ``summary["with_edges"]`` and ``["without_edges"]``.
    """

    @property
    def cycles(self) -> Dict[Optional[str], Dict[str, Any]]:
        """The cycles' summaries by variant (``None`` for a single cycle)."""
        s = self.summary
        if "with_edges" in s and "without_edges" in s:
            return {"with_edges": s["with_edges"], "without_edges": s["without_edges"]}
        return {None: s}

    @property
    def first(self) -> Dict[str, Any]:
        """The only cycle's summary, or the variant with edges."""
        return next(iter(self.cycles.values()))

    @property
    def te_peak_to_peak_urad(self) -> float:
        """Loaded TE peak-to-peak at the pinion (µrad)."""
        return self.first["te_peak_to_peak_urad"]

    @property
    def te_peak_to_peak_arcsec(self) -> float:
        """Loaded TE peak-to-peak at the gear (arcsec)."""
        return self.first["te_peak_to_peak_arcsec"]

    @property
    def max_pressure_mpa(self) -> float:
        """Largest contact pressure over the cycle (MPa)."""
        return self.first["max_pressure_mpa"]

    @property
    def steps(self) -> List[Dict[str, Any]]:
        """Per position: roll angle, load shares, TE, solver figures."""
        return self.first["steps"]

    @property
    def cycle(self):
        """``ltca_cycle.csv`` as a DataFrame."""
        return self.tables["ltca_cycle"]

    @property
    def pairs(self):
        """``ltca_positions.csv`` (per position and tooth pair) as a DataFrame."""
        return self.tables["ltca_positions"]

    @property
    def points(self):
        """``ltca_points.csv`` (per contact point) as a DataFrame."""
        return self.tables["ltca_points"]


class FeResult(Result):
    """``flank run``: FE contact over the mesh cycle
    (``flank::mesh_cycle::summary::RunSummary``). Tables: spur/helical
    ``mesh_cycle`` (per roll angle: ``force_pair<k>_n``, ``share_pair<k>``,
    ``max_pressure_pair<k>_mpa``, ``te_urad``, ``te_um``); bevel/hypoid
    ``positions`` and ``contact_pattern``."""

    @property
    def cycle(self):
        """``mesh_cycle.csv`` (spur/helical) as a DataFrame."""
        return self.tables["mesh_cycle"]


class CompareResult(Result):
    """``flank compare``: the LTCA against FE contact at the same positions
    (``compare.json``: ``load_sharing_rel_err``, ``te_rel_err``,
    ``pmax_rel_err`` as fractions, ``ltca_cycle_s``, ``fe_cycle_s``)."""


class ComplianceResult(Result):
    """``flank compliance``: the bodies' tensors written into ``folder``
    (``<body>.compliance.bin``, or ``.h5`` with the feature ``hdf5``)."""

    def tensor(self, body: str) -> "ComplianceTensor":
        """The tensor of ``body`` (``pinion``, ``gear``) read from the run's files."""
        from . import read_compliance_tensor

        b = self.summary["bodies"][body]
        path = Path(b["file"])
        if not path.is_absolute() and self.folder is not None and not path.exists():
            path = self.folder / path.name
        return read_compliance_tensor(path)


class ComplianceTensor:
    """A body's nodal compliance tensor: ``matrix`` C (3N × 3N, mm/N, DOF
    order node-major x, y, z; the file's buffer handed to numpy, not
    copied), ``positions`` and ``normals`` (N × 3, mm and unit outward),
    ``uv`` (N × 2 flank parameters), ``labels`` (deck node labels),
    ``set_of`` (index into ``sets``, the flank node sets) and ``meta``
    (body, mesh hash, materials, units, method)."""

    def __init__(self, raw: Dict[str, Any]):
        self.meta: Dict[str, Any] = json.loads(raw["meta"])
        self.sets: List[str] = raw["sets"]
        self.labels = raw["labels"]
        self.set_of = raw["set_of"]
        self.uv = raw["uv"]
        self.positions = raw["positions"]
        self.normals = raw["normals"]
        self.matrix = raw["matrix"]

    @property
    def nodes(self) -> int:
        """N, the flank nodes."""
        return len(self.labels)

    def __repr__(self) -> str:
        n = self.matrix.shape[0]
        return f"ComplianceTensor(body={self.meta.get('body')!r}, nodes={self.nodes}, C {n}×{n} mm/N)"


class CampaignResult(Result):
    """``flank campaign run``: ``report`` (jobs, skipped, finished, failed,
    workers, wall_s; empty after :func:`flank.campaign_collect`) and
    ``table`` (one row per job: inputs, figures, seconds, status, as
    ``table.csv``) as a DataFrame."""

    def __init__(self, raw: Dict[str, Any], folder: Optional[Path]):
        # a collect without a run has no report
        report = raw.get("report", {})
        super().__init__(report, folder)
        self.report: Dict[str, Any] = report
        self._raw = raw

    @property
    def table(self):
        """One row per job: index, id, analysis, status, the inputs, the figures, seconds."""
        import pandas as pd

        rows = []
        for r in self._raw["rows"]:
            row = {"index": r["index"], "id": r["id"], "analysis": r["analysis"], "status": r["status"]}
            row.update(r["inputs"])
            row.update(r["figures"])
            row["seconds"] = r["seconds"]
            rows.append(row)
        return pd.DataFrame(rows)


def output_folder(out) -> tuple[Path, Any]:
    """The folder a run writes into: ``out``, or a temporary folder owned by
    the result (removed when the result is)."""
    if out is not None:
        return Path(out), None
    tmp = tempfile.TemporaryDirectory(prefix="flank_")
    return Path(tmp.name), tmp

