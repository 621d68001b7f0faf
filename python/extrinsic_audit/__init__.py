"""extrinsic-audit from Python: what a robot's LiDAR extrinsic does to
degeneracy detection, numpy in and out.

>>> import extrinsic_audit as ea
>>> robot = ea.load(["robot.urdf"], joints={"torso_joint": 0.2})  # doctest: +SKIP
>>> T = robot.transform("base_link", "lidar")        # 4x4, p_base = R p_lidar + t
>>> report = robot.report("base_link", "lidar")      # report.to_dict(): the CLI's JSON

Conventions are the CLI's: ``transform(frm, to)`` is the pose of ``to`` in
``frm`` (what ``tf2_echo FRM TO`` prints), metres and radians, twists and
per-axis footprints rotation first. Errors raise :class:`AuditError`
subclasses carrying the diagnostic's ``code``, ``file``, ``line`` and
``message``; warnings go through :mod:`warnings` as :class:`AuditWarning`
subclasses. Every call that reads files or points releases the GIL.
"""

from __future__ import annotations

import json
import os
from typing import Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._errors import (
    AuditError,
    AuditWarning,
    ConventionWarning,
    FrameError,
    GraphWarning,
    InputError,
    JointWarning,
    NumericWarning,
    UsageError,
    warn_all,
)
from ._reports import (
    AXES,
    CheckReport,
    DegeneracyReport,
    DiffReport,
    FamilyResult,
    PairReport,
    Report,
    RigReport,
    RunReport,
    ScanResult,
    Screw,
    SurveyReport,
)

__version__ = _native.__version__

# Errors, warnings and reports print as the package's own names.
for _cls in (AuditError, InputError, FrameError, UsageError, AuditWarning, ConventionWarning,
             NumericWarning, JointWarning, GraphWarning):
    _cls.__module__ = __name__
del _cls

PathLike = Union[str, "os.PathLike[str]"]
Renames = Union[Mapping[str, str], Iterable[Union[str, Tuple[str, str], Tuple[Optional[str], str, str]]]]

__all__ = [
    "AXES",
    "AuditError",
    "AuditWarning",
    "CheckReport",
    "ConventionWarning",
    "DegeneracyReport",
    "DiffReport",
    "FamilyResult",
    "FrameError",
    "GraphWarning",
    "InputError",
    "JointWarning",
    "NumericWarning",
    "PairReport",
    "Report",
    "RigReport",
    "Robot",
    "RunReader",
    "RunReport",
    "ScanResult",
    "Screw",
    "SurveyReport",
    "UsageError",
    "check",
    "degeneracy",
    "degeneracy_scan",
    "diff",
    "load",
    "run",
    "survey",
]


def _paths(paths: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    return [os.fspath(p) for p in paths]


def _rename(r) -> Tuple[Optional[str], str, str]:
    """``"[FILE:]OLD=NEW"``, ``(old, new)`` or ``(file, old, new)``."""
    if isinstance(r, str):
        spec, sep, new = r.rpartition("=")
        if not sep:
            raise UsageError(f"renames: expected [FILE:]OLD=NEW, found `{r}`")
        file, colon, old = spec.rpartition(":")
        return (file if colon else None, old, new)
    r = tuple(r)
    if len(r) == 2:
        return (None, r[0], r[1])
    if len(r) == 3:
        return r  # type: ignore[return-value]
    raise UsageError(f"renames: expected (old, new) or (file, old, new), found {r!r}")


def _load_args(renames=None, joints=None, xacro_args=None, package_paths=None, key=None,
               invert=False, input_format=None, urdf_version=None, max_file_size=None,
               xacro="native", xacro_path=None, tf_static_topics=(), tf_topics=(),
               description_topics=()) -> dict:
    if isinstance(renames, Mapping):
        renames = list(renames.items())
    if xacro_path is not None and not isinstance(xacro_path, str):
        xacro_path = os.pathsep.join(os.fspath(p) for p in xacro_path)
    return {
        "renames": [_rename(r) for r in (renames or [])],
        "joints": {str(k): float(v) for k, v in (joints or {}).items()},
        "xacro_args": {str(k): str(v) for k, v in (xacro_args or {}).items()},
        "package_paths": _paths(package_paths or []),
        "key": key,
        "invert": bool(invert),
        "input_format": input_format,
        "urdf_version": None if urdf_version is None else str(urdf_version),
        "max_file_size": None if max_file_size is None else int(max_file_size),
        "xacro": str(xacro),
        "xacro_path": xacro_path,
        "tf_static_topics": _topics(tf_static_topics, "tf_static_topics"),
        "tf_topics": _topics(tf_topics, "tf_topics"),
        "description_topics": _topics(description_topics, "description_topics"),
    }


def _topics(topics, what: str) -> List[str]:
    """One topic or a sequence of them."""
    if isinstance(topics, str):
        return [topics]
    out = list(topics)
    if not all(isinstance(t, str) for t in out):
        raise UsageError(f"{what}: expected topic names, found {out!r}")
    return out


def _pitch_tol(v: Union[None, str, float]) -> Optional[str]:
    return None if v is None else str(v)


class Robot:
    """A robot's frames, loaded from its files into one tree (see :func:`load`)."""

    def __init__(self, native: "_native.Robot",
                 sigma: Optional[Tuple[float, float]] = None):
        self._robot = native
        self._sigma = sigma

    def frames(self) -> List[str]:
        """Every frame, sorted."""
        return self._robot.frames()

    def joints(self) -> List[str]:
        """The movable joints' names (what ``joints=`` sets)."""
        return self._robot.joints()

    def notes(self) -> List[str]:
        """Notes on how the files were read (a redundant edge that agrees)."""
        return self._robot.notes()

    def frame_pair(self, frm: Optional[str] = None, to: Optional[str] = None) -> Tuple[str, str]:
        """The pair a report is on: both given, a rig file's pair, or the only edge."""
        return self._robot.frame_pair(frm, to)

    def transform(self, frm: str, to: str) -> np.ndarray:
        """The pose of ``to`` in ``frm`` as a 4x4 float64 array:
        ``p_frm = T[:3, :3] @ p_to + T[:3, 3]``. A movable joint on the chain
        not set by ``joints=`` warns (:class:`JointWarning`)."""
        m, ws = self._robot.transform(frm, to)
        if ws:
            warn_all(ws)
        return m

    def transform_parts(self, frm: str, to: str) -> Tuple[np.ndarray, np.ndarray]:
        """The same pose as ``(R, t)``: a 3x3 rotation and a translation (m)."""
        m = self.transform(frm, to)
        return m[:3, :3].copy(), m[:3, 3].copy()

    def report(self, frm: Optional[str] = None, to: Optional[str] = None, *,
               ells: Optional[Sequence[float]] = None,
               pitch_tol: Union[None, str, float] = None,
               kappa: Optional[float] = None, lam: Optional[float] = None) -> RigReport:
        """The rig report of ``frm -> to`` (lever arm, screw, adjoint bands,
        adapted metric, every detector family's verdict), as the CLI's
        ``audit FILES --from FRM --to TO`` (``ells`` its ``--ell``,
        ``pitch_tol`` ``--pitch-tol``, ``kappa``/``lam`` ``--kappa``/``--lambda``;
        the uncertainty ``load``'s ``sigma_t``/``sigma_r``)."""
        frm, to = self.frame_pair(frm, to)
        if (kappa is None) != (lam is None):
            raise UsageError("kappa and lam: give both or neither")
        kl = None if kappa is None else (float(kappa), float(lam))
        ells_ = None if ells is None else [float(e) for e in ells]
        text, ws = self._robot.report(frm, to, ells_, _pitch_tol(pitch_tol), kl, self._sigma)
        if ws:
            warn_all(ws)
        return RigReport._from_json(text)

    def frame_tree(self, frm: Optional[str] = None, to: Optional[str] = None) -> Report:
        """The frame tree (``audit FILES --frames --format json``), the chain
        ``frm -> to`` highlighted when both are given."""
        return Report._from_json(self._robot.frame_tree(frm, to))

    def __repr__(self) -> str:
        return f"<Robot {len(self.frames())} frames>"


def load(paths: Union[PathLike, Sequence[PathLike]], *, renames: Optional[Renames] = None,
         joints: Optional[Mapping[str, float]] = None,
         xacro_args: Optional[Mapping[str, str]] = None,
         package_paths: Optional[Sequence[PathLike]] = None, key: Optional[str] = None,
         invert: bool = False, input_format: Optional[str] = None,
         sigma_t: Optional[float] = None, sigma_r: Optional[float] = None,
         urdf_version: Optional[str] = None, max_file_size: Optional[int] = None,
         xacro: str = "native", xacro_path: Union[None, str, Sequence[PathLike]] = None,
         tf_static_topics: Union[str, Sequence[str]] = (),
         tf_topics: Union[str, Sequence[str]] = (),
         description_topics: Union[str, Sequence[str]] = ()) -> Robot:
    """Load calibration files (URDF, xacro, launch files, TF dumps, bags,
    LIO/Kalibr YAML, rig TOML, ...) into one frame tree, as the CLI reads
    them: ``renames`` (``{"old": "new"}``, ``"[FILE:]OLD=NEW"`` strings or
    tuples: ``--rename``), ``joints`` (``--joint``, radians or metres; movable
    joints not named are at 0), ``xacro_args`` (``--arg``), ``package_paths``
    (``--package-path``), ``key`` and ``invert`` (``--key``, ``--invert``),
    ``input_format`` (``--input-format``), ``urdf_version`` (``--urdf-version``,
    ``"1.0"`` to ``"1.2"``), ``max_file_size`` (``--max-file-size``, bytes),
    ``xacro`` (``--xacro``: ``"native"`` or ``"external"``, the ROS ``xacro``
    program, looked for on ``xacro_path``, a ``PATH``-style string or a list
    of folders, default the process's ``PATH``), a bag's topics
    (``tf_static_topics``, ``tf_topics``, ``description_topics``:
    ``--tf-static-topic``, ``--tf-topic``, ``--description-topic``). ``sigma_t``
    (m) and ``sigma_r`` (degrees) are the calibration's uncertainty per edge
    that :meth:`Robot.report` propagates (``--sigma-t``, ``--sigma-r``). The
    files' warnings are emitted."""
    sigma = None
    if sigma_t is not None or sigma_r is not None:
        sigma = (float(sigma_t or 0.0), float(sigma_r or 0.0))
    native = _native.load(_paths(paths), _load_args(
        renames, joints, xacro_args, package_paths, key, invert, input_format, urdf_version,
        max_file_size, xacro, xacro_path, tf_static_topics, tf_topics, description_topics))
    ws = native.warnings()
    if ws:
        warn_all(ws)
    return Robot(native, sigma)


def check(paths: Union[PathLike, Sequence[PathLike]], *, baseline: Optional[PathLike] = None,
          write_baseline: Optional[PathLike] = None, prune: bool = False,
          exclude: Sequence[str] = (), pairs: Sequence[Tuple[str, str]] = (),
          max_lever_arm: Optional[float] = None, require_zero_pitch: bool = False,
          max_translation_drift: Optional[float] = None,
          max_rotation_drift: Optional[float] = None,
          pitch_tol: Union[None, str, float] = None,
          joints: Optional[Mapping[str, float]] = None, allow: Sequence[str] = (),
          deny: Sequence[str] = (), deny_warnings: bool = False) -> CheckReport:
    """``audit check PATHS``: the CI gate on calibration files, against a
    ``baseline`` when given. Returns the report (``.ok``, ``.findings``);
    findings of severity warning are also emitted as warnings."""
    args = {
        "baseline": None if baseline is None else os.fspath(baseline),
        "write_baseline": None if write_baseline is None else os.fspath(write_baseline),
        "prune": bool(prune),
        "exclude": list(exclude),
        "pairs": [tuple(p) for p in pairs],
        "max_lever_arm": max_lever_arm,
        "require_zero_pitch": bool(require_zero_pitch),
        "max_translation_drift": max_translation_drift,
        "max_rotation_drift": max_rotation_drift,
        "pitch_tol": _pitch_tol(pitch_tol),
        "joints": {str(k): float(v) for k, v in (joints or {}).items()},
        "allow": list(allow),
        "deny": list(deny),
        "deny_warnings": bool(deny_warnings),
    }
    text, code = _native.check(_paths(paths), args)
    report = CheckReport(json.loads(text), code)
    ws = [(f["code"], "warning", f.get("file"), f.get("line"), f.get("column"), f["message"], None)
          for f in report.findings if f["severity"] == "warning"]
    if ws:
        warn_all(ws)
    return report


def diff(old: PathLike, new: PathLike, frm: Optional[str] = None, to: Optional[str] = None, *,
         key: Optional[str] = None, invert: bool = False, key_old: Optional[str] = None,
         key_new: Optional[str] = None, invert_old: bool = False, invert_new: bool = False,
         renames: Optional[Renames] = None, joints: Optional[Mapping[str, float]] = None,
         ells: Optional[Sequence[float]] = None, pitch_tol: Union[None, str, float] = None,
         tolerance: Optional[Tuple[float, float]] = None) -> DiffReport:
    """``audit diff OLD NEW``: what changed on the ``frm -> to`` chain
    between two calibrations; ``tolerance`` is ``(mm, deg)``. ``.exceeded``
    says whether a change is beyond it (the CLI's exit code 1). Without
    ``frm``/``to``, where neither file declares a pair, every edge present in
    both files is compared and edges on one side only are listed (``from``,
    ``to`` and ``chain`` are then ``None``; an edge on one side only exceeds)."""
    args = {
        "frm": frm,
        "to": to,
        "key_old": key if key is not None else key_old,
        "key_new": key if key is not None else key_new,
        "invert_old": bool(invert or invert_old),
        "invert_new": bool(invert or invert_new),
        "ells": None if ells is None else [float(e) for e in ells],
        "pitch_tol": _pitch_tol(pitch_tol),
        "tolerance": None if tolerance is None else (float(tolerance[0]), float(tolerance[1])),
    }
    text, ws, exceeded = _native.diff(os.fspath(old), os.fspath(new), args,
                                      _load_args(renames, joints))
    if ws:
        warn_all(ws)
    return DiffReport(json.loads(text), exceeded)


def survey(paths: Union[PathLike, Sequence[PathLike]], *, all: bool = False,
           sort: Optional[str] = None, pair: Optional[Tuple[str, str]] = None,
           pitch_tol: Union[None, str, float] = None,
           xacro_args: Optional[Mapping[str, str]] = None,
           package_paths: Optional[Sequence[PathLike]] = None, key: Optional[str] = None,
           invert: bool = False) -> SurveyReport:
    """``audit survey PATHS``: one row per rig over many files (``all``:
    placeholders and duplicates too; ``sort`` a column such as
    ``"lever-arm"``; ``pair`` the ``(frm, to)`` for files that are not rig files)."""
    args = {"all": bool(all), "sort": sort, "pair": None if pair is None else tuple(pair),
            "pitch_tol": _pitch_tol(pitch_tol)}
    text, ws = _native.survey(_paths(paths), args,
                              _load_args(None, None, xacro_args, package_paths, key, invert))
    if ws:
        warn_all(ws)
    return SurveyReport._from_json(text)


def _rows(a, what: str) -> np.ndarray:
    """``a`` as a C-contiguous (N, 3) float64 or float32 array: the array
    itself when it already is one (read in place, no copy), else a copy."""
    arr = np.asarray(a)
    dtype = arr.dtype if arr.dtype in (np.float32, np.float64) else np.float64
    arr = np.ascontiguousarray(arr, dtype=dtype)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise UsageError(f"{what}: expected an (N, 3) array, found shape {arr.shape}")
    return arr


def _detector_args(tau, ells, frame, show_matrices, voxel, radius, knn, min_neighbours,
                   min_planarity, viewpoint) -> dict:
    f = None
    if frame is not None:
        f = np.asarray(frame, dtype=float)
        if f.shape != (4, 4):
            raise UsageError(f"frame: expected a 4x4 pose, found shape {f.shape}")
        f = f.tolist()
    return {
        "tau": tau, "ells": None if ells is None else [float(e) for e in ells], "frame": f,
        "show_matrices": bool(show_matrices), "voxel": voxel, "radius": radius, "knn": knn,
        "min_neighbours": min_neighbours, "min_planarity": min_planarity,
        "viewpoint": None if viewpoint is None else [float(v) for v in viewpoint],
    }


def degeneracy(points, normals=None, weights=None, *, tau: Optional[float] = None,
               ells: Optional[Sequence[float]] = None, frame=None, show_matrices: bool = False,
               voxel: Optional[float] = None, radius: Optional[float] = None,
               knn: Optional[int] = None, min_neighbours: Optional[int] = None,
               min_planarity: Optional[float] = None, viewpoint=None) -> DegeneracyReport:
    """Every detector family on points held in numpy arrays: ``points`` and
    ``normals`` (N, 3) float64 or float32 (read in place when C-contiguous;
    other layouts and dtypes are copied once), ``weights`` (N,). Without
    ``normals`` the scan is raw and normals are estimated (``voxel``,
    ``radius``, ``knn``, ``min_neighbours``, ``min_planarity``,
    ``viewpoint``: ``audit degeneracy --estimate-normals``'s options).
    ``frame`` is the 4x4 pose of the body frame the matrices are expressed in,
    in the points' frame. As ``audit degeneracy --format json``."""
    xyz = _rows(points, "points")
    nrm = None if normals is None else _rows(normals, "normals")
    w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float64)
    args = _detector_args(tau, ells, frame, show_matrices, voxel, radius, knn, min_neighbours,
                          min_planarity, viewpoint)
    return DegeneracyReport._from_json(_native.degeneracy(xyz, nrm, w, args))


def degeneracy_scan(path: PathLike, *, estimate_normals: bool = False,
                    tau: Optional[float] = None, ells: Optional[Sequence[float]] = None,
                    frame=None, show_matrices: bool = False, voxel: Optional[float] = None,
                    radius: Optional[float] = None, knn: Optional[int] = None,
                    min_neighbours: Optional[int] = None, min_planarity: Optional[float] = None,
                    viewpoint=None) -> DegeneracyReport:
    """Every detector family on a point file (CSV, PLY, PCD with normals; any
    of them or LAS/LAZ with ``estimate_normals``): ``audit degeneracy FILE``."""
    args = _detector_args(tau, ells, frame, show_matrices, voxel, radius, knn, min_neighbours,
                          min_planarity, viewpoint)
    return DegeneracyReport._from_json(
        _native.degeneracy_scan(os.fspath(path), bool(estimate_normals), args))


def _bound(b, what: str) -> Optional[str]:
    """A scan index (int) or seconds after the first scan (``"12.5s"``)."""
    if b is None:
        return None
    if isinstance(b, bool) or not isinstance(b, (int, str)):
        raise UsageError(f"{what}: expected a scan index (int) or seconds (\"12.5s\"), found {b!r}")
    return str(b)


class RunReader:
    """A recorded run being read (see :func:`run`): iterate for one
    :class:`ScanResult` per scan (or pair) in run order, then call
    :meth:`finish` for the summary."""

    def __init__(self, native: "_native.Run"):
        self._run = native

    @property
    def frames(self) -> List[str]:
        """The frames every result is reported in, ``scan`` (the scan's own) first."""
        return self._run.frames

    @property
    def families(self) -> List[str]:
        """The families' keys (``point_displacement``, ``characteristic_length@1m``, ...)."""
        return self._run.families

    @property
    def pairs(self) -> bool:
        """Whether the results are scan pairs."""
        return self._run.pairs

    def __iter__(self) -> "RunReader":
        return self

    def __next__(self) -> ScanResult:
        return ScanResult._from_json(next(self._run))

    def finish(self) -> RunReport:
        """The summary (``audit run --format json``): scans read and skipped,
        degenerate intervals, label changes between frames. The scans not yet
        taken are read first; the run's warnings (skipped scans, damage) are
        emitted."""
        text, ws = self._run.finish()
        if ws:
            warn_all(ws)
        return RunReport._from_json(text)

    def __repr__(self) -> str:
        return f"<RunReader {'pairs' if self.pairs else 'scans'} in {len(self.frames)} frames>"


def run(paths: Union[PathLike, Sequence[PathLike]], *, topic: Optional[str] = None,
        start: Union[None, int, str] = None, end: Union[None, int, str] = None, every: int = 1,
        lidar_frame: Optional[str] = None, frames: Sequence[str] = (), all_frames: bool = False,
        extrinsics: Sequence[PathLike] = (), rig_frames: Sequence[PathLike] = (),
        tau: Optional[float] = None, ells: Optional[Sequence[float]] = None,
        voxel: Optional[float] = None, radius: Optional[float] = None,
        knn: Optional[int] = None, min_neighbours: Optional[int] = None, viewpoint=None,
        estimate_normals: bool = False, pairs: bool = False, pair_step: int = 1,
        gate: Optional[float] = None, poses: Optional[PathLike] = None,
        poses_format: Optional[str] = None, calib: Optional[PathLike] = None,
        poses_topic: Optional[str] = None, poses_frame: Optional[str] = None,
        threads: int = 0, xacro_args: Optional[Mapping[str, str]] = None,
        package_paths: Optional[Sequence[PathLike]] = None,
        tf_static_topics: Union[str, Sequence[str]] = (),
        tf_topics: Union[str, Sequence[str]] = (),
        description_topics: Union[str, Sequence[str]] = ()) -> RunReader:
    """``audit run PATHS``: every scan of a bag's PointCloud2 ``topic``, of a
    KITTI sequence or of a folder of point files through the detector, in the
    scan frame and the body frames of the run's transforms (``frames``,
    ``all_frames``, ``extrinsics``) or of rig files (``rig_frames``). Scans
    from ``start`` to ``end`` (an index, or ``"12.5s"`` after the first
    scan), every ``every``-th. Normals from the scans' fields, or estimated
    (``voxel`` grid, default 0.1 m, 0 for none; ``radius``, ``knn``,
    ``min_neighbours``, ``viewpoint``). With ``pairs``, each scan against the
    ``pair_step``-th before it at their relative pose (``poses`` file and
    ``poses_format``, ``calib``, ``poses_topic``, ``poses_frame``, ``gate``).
    Returns a :class:`RunReader`; each scan is read when the iteration asks
    for it (GIL released), so a long run streams."""
    args = {
        "topic": topic, "start": _bound(start, "start"), "end": _bound(end, "end"),
        "every": int(every), "lidar_frame": lidar_frame, "frames": list(frames),
        "all_frames": bool(all_frames), "extrinsics": _paths(extrinsics),
        "rig_frames": _paths(rig_frames), "tau": tau,
        "ells": None if ells is None else [float(e) for e in ells], "voxel": voxel,
        "radius": radius, "knn": knn, "min_neighbours": min_neighbours,
        "viewpoint": None if viewpoint is None else [float(v) for v in viewpoint],
        "estimate_normals": bool(estimate_normals), "pairs": bool(pairs),
        "pair_step": int(pair_step), "gate": gate,
        "poses": None if poses is None else os.fspath(poses), "poses_format": poses_format,
        "calib": None if calib is None else os.fspath(calib), "poses_topic": poses_topic,
        "poses_frame": poses_frame, "threads": int(threads),
    }
    load = _load_args(None, None, xacro_args, package_paths, tf_static_topics=tf_static_topics,
                      tf_topics=tf_topics, description_topics=description_topics)
    return RunReader(_native.run(_paths(paths), args, load))
