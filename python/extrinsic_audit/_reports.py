"""Typed reports: each holds the dict of its JSON schema (``docs/schemas``,
what the CLI prints with ``--format json``) and exposes the fields a script
reads most as typed attributes, arrays as numpy arrays. ``to_dict()`` gives
the whole dict, equal to ``json.loads`` of the CLI's output."""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

#: The per-axis order of twists and footprints: rotation first.
AXES = ("rot-x", "rot-y", "rot-z", "trans-x", "trans-y", "trans-z")


class Report:
    """A report: its schema's dict, read through typed attributes."""

    def __init__(self, data: Dict[str, Any]):
        self._data = data

    @classmethod
    def _from_json(cls, text: str):
        return cls(json.loads(text))

    def to_dict(self) -> Dict[str, Any]:
        """The report as the dict of its JSON schema (a copy)."""
        return copy.deepcopy(self._data)

    def to_json(self, indent: Optional[int] = 2) -> str:
        """The report as JSON text."""
        return json.dumps(self._data, indent=indent)

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    @property
    def warnings(self) -> List[str]:
        """The warning lines met while making the report."""
        return list(self._data.get("warnings", []))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._summary()}>"

    def _summary(self) -> str:
        return ""


class Screw:
    """The screw of a rig's transform (Chasles): kind, the translation ``h``
    along the rotation axis, its pitch and the verdict on zero pitch."""

    def __init__(self, d: Dict[str, Any]):
        self.kind: str = d["kind"]
        self.translation_along_axis_m: Optional[float] = d.get("translation_along_axis_m")
        self.pitch_m_per_rad: Optional[float] = d.get("pitch_m_per_rad")
        self.pitch_verdict: Optional[str] = d.get("pitch_verdict")
        self.axis_point_m = None if d.get("axis_point_m") is None else np.array(d["axis_point_m"])

    def __repr__(self) -> str:
        return f"Screw(kind={self.kind!r}, h={self.translation_along_axis_m!r}, verdict={self.pitch_verdict!r})"


class PairReport(Report):
    """A report on one frame pair."""

    @property
    def frm(self) -> str:
        """The parent frame (JSON ``from``)."""
        return self._data["from"]

    @property
    def to(self) -> str:
        """The child frame: the report is on the pose of ``to`` in ``frm``."""
        return self._data["to"]


class RigReport(PairReport):
    """The rig report of a frame pair (``audit FILES --from A --to B``)."""

    @property
    def matrix(self) -> np.ndarray:
        """The 4x4 pose of ``to`` in ``frm``, ``p_frm = R p_to + t``."""
        m = np.eye(4)
        m[:3, :3] = self.R
        m[:3, 3] = self.t
        return m

    @property
    def R(self) -> np.ndarray:
        """The rotation (3x3)."""
        return np.array(self._data["transform"]["rotation_matrix"], dtype=float)

    @property
    def t(self) -> np.ndarray:
        """The translation (m)."""
        return np.array(self._data["transform"]["translation_m"], dtype=float)

    @property
    def lever_arm_m(self) -> float:
        """``|t|`` (m)."""
        return self._data["lever_arm_m"]

    @property
    def angle_deg(self) -> float:
        """The rotation angle (deg)."""
        return self._data["rotation"]["angle_deg"]

    @property
    def screw(self) -> Screw:
        """The transform's screw."""
        return Screw(self._data["screw"])

    @property
    def adjoint_singular_values(self) -> np.ndarray:
        """The singular values of ``Ad(T)``, descending."""
        return np.array(self._data["adjoint"]["singular_values"], dtype=float)

    @property
    def bands(self) -> Dict[float, Tuple[float, float]]:
        """The certificate band ``[lo, hi]`` of each characteristic length."""
        return {c["ell_m"]: tuple(c["band"]) for c in self._data["certificate"]}

    @property
    def adapted_metric_exists(self) -> bool:
        """Whether a constant metric adapted to this rig exists (zero pitch)."""
        return self._data["adapted_metric"]["exists"]

    @property
    def invariant_families(self) -> List[str]:
        """The detector families whose eigenvalues are frame-invariant here."""
        return [d["family"] for d in self._data["detectors"] if d["invariant_on_rig"]]

    def _summary(self) -> str:
        return f"{self.frm} -> {self.to}, lever arm {self.lever_arm_m:.3f} m, screw {self.screw.kind}"


class CheckReport(Report):
    """``audit check``: the files checked and every finding."""

    def __init__(self, data: Dict[str, Any], exit_code: int):
        super().__init__(data)
        self.exit_code: int = exit_code

    @property
    def ok(self) -> bool:
        """No problem found (the CLI's exit code 0)."""
        return self.exit_code == 0

    @property
    def files_checked(self) -> int:
        return self._data["files_checked"]

    @property
    def problems(self) -> int:
        return self._data["problems"]

    @property
    def findings(self) -> List[Dict[str, Any]]:
        """Each finding: severity, code, file, line, column, message."""
        return copy.deepcopy(self._data["findings"])

    def _summary(self) -> str:
        return f"{self.files_checked} files, {self.problems} problems"


class DiffReport(PairReport):
    """``audit diff OLD NEW``: what changed on the chain, edge by edge;
    ``exceeded``: a change beyond the tolerance (the CLI's exit code 1)."""

    def __init__(self, data: Dict[str, Any], exceeded: bool):
        super().__init__(data)
        self.exceeded: bool = exceeded

    def _summary(self) -> str:
        verdict = "beyond" if self.exceeded else "within"
        if self.frm is None:
            # Whole files compared (no --from/--to, no declared pair).
            return f"whole files, {len(self._data['edges'])} edges, {verdict} tolerance"
        return f"{self.frm} -> {self.to}, {verdict} tolerance"


class SurveyReport(Report):
    """``audit survey``: one row per rig."""

    @property
    def rigs(self) -> List[Dict[str, Any]]:
        """One dict per rig (id, frames, lever arm, screw, band at l = 1 m, ...)."""
        return copy.deepcopy(self._data["rigs"])

    def to_pandas(self):
        """The rigs as a pandas DataFrame (pandas imported on demand)."""
        import pandas as pd  # noqa: PLC0415 (optional dependency)

        return pd.DataFrame(self._data["rigs"])

    def _summary(self) -> str:
        return f"{len(self._data['rigs'])} rigs"


class FamilyResult:
    """One detector family's answer: the generalized eigenvalues of
    ``H v = lambda M v`` (ascending), the threshold and how many are below it."""

    def __init__(self, d: Dict[str, Any]):
        self._d = d
        self.family: str = d["family"]
        ev = d.get("eigenvalues")
        self.eigenvalues: Optional[np.ndarray] = None if ev is None else np.array(ev, dtype=float)
        self.degenerate_count: Optional[int] = d.get("degenerate_count")

    def __getitem__(self, key: str) -> Any:
        return self._d[key]

    def __repr__(self) -> str:
        return f"FamilyResult({self.family!r}, degenerate_count={self.degenerate_count!r})"


class DegeneracyReport(Report):
    """``audit degeneracy``: every family on one cloud, the degenerate
    subspace and its per-axis footprint (axes in :data:`AXES` order)."""

    @property
    def points(self) -> int:
        return self._data["points"]

    @property
    def families(self) -> List[FamilyResult]:
        return [FamilyResult(f) for f in self._data["families"]]

    def family(self, name: str) -> FamilyResult:
        """The result of one family by name (``point-displacement``, ...)."""
        for f in self._data["families"]:
            if f["family"] == name:
                return FamilyResult(f)
        raise KeyError(name)

    @property
    def footprint(self) -> np.ndarray:
        """Per axis: the point-displacement degenerate subspace reaches it."""
        return np.array(self._data["footprint"], dtype=bool)

    @property
    def footprint_scores(self) -> np.ndarray:
        return np.array(self._data["footprint_scores"], dtype=float)

    def _summary(self) -> str:
        axes = [a for a, f in zip(AXES, self._data["footprint"]) if f]
        return f"{self.points} points, degenerate along {axes or 'nothing'}"


class ScanResult(Report):
    """One scan's (or pair's) result of a run: its JSON line
    (``audit run --jsonl``, ``docs/schemas/run-scan.schema.json``)."""

    @property
    def index(self) -> int:
        """The scan's place in the run (a pair's source's)."""
        return self._data["index"]

    @property
    def time_s(self) -> Optional[float]:
        """Seconds after the run's first scan."""
        return self._data["time_s"]

    @property
    def skipped(self) -> Optional[str]:
        """Why the scan was skipped (``empty``, ``invalid-cloud``, ...), or ``None``."""
        return self._data["reason"]

    @property
    def points(self) -> Optional[int]:
        """Points in ``H`` (a pair's correspondences)."""
        return self._data["points"]

    def family(self, frame: str, family: str) -> Optional[Dict[str, Any]]:
        """``family`` (a key of :attr:`RunReader.families`) in ``frame``, or
        ``None`` where the scan's transforms do not reach the frame."""
        for f in self._data["frames"]:
            if f["frame"] == frame:
                for x in f["families"] or []:
                    if x["family"] == family:
                        return x
                return None
        raise KeyError(f"no frame {frame!r} in this run")

    def eigenvalues(self, frame: str, family: str = "point_displacement") -> Optional[np.ndarray]:
        """The six generalized eigenvalues of ``H v = lambda M v``, ascending."""
        x = self.family(frame, family)
        ev = None if x is None else x["eigenvalues"]
        return None if ev is None else np.array(ev)

    def _summary(self) -> str:
        return f"scan {self.index}" + (f" skipped ({self.skipped})" if self.skipped else "")


class RunReport(Report):
    """A run's summary (``audit run --format json``, ``docs/schemas/run.schema.json``)."""

    @property
    def read(self) -> int:
        """Scans (or pairs) read."""
        return self._data["read"]

    @property
    def analysed(self) -> int:
        """Scans (or pairs) analysed."""
        return self._data["analysed"]

    def _summary(self) -> str:
        return f"{self.analysed} of {self.read} {self._data['unit']} analysed"
