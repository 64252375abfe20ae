"""Recorded runs: read a real swarm's log (CSV, MCAP, rosbag2) into per-robot samples, and write ours.

A recorded run is what a swarm logged somewhere else -- on robots, in Gazebo or Webots, through
ROS 2 -- reduced to what the properties read: every robot's poses over time and, where the log
has them, its spanning-tree parent.  This module only reads and writes files; aligning the
samples on a common clock and judging them is :mod:`swarmproof.checkers.recorded`.

Formats (docs/recorded-runs.md has the details and a walkthrough):

* **CSV**: a header row, then one row per pose sample: ``t, id, x, y, theta`` and optionally
  ``parent`` (empty or ``-1``: none).  ``t`` in seconds, ``theta`` in radians.  Columns in any
  order; other columns are ignored and listed in the report.  Rows of different robots may
  interleave in any order; within one robot ``t`` must increase.
* **MCAP** (a ``.mcap`` file) with ROS 2 messages (``ros2msg`` schemas, CDR), read with ``mcap``
  and ``mcap-ros2-support``.
* **rosbag2** (a bag's folder with its ``metadata.yaml``), either storage (``sqlite3`` or
  ``mcap``), read with ``rosbags``, which needs no ROS install.

In the bags, one topic per robot carries its pose (``--topics``, default ``/robot_{id}/pose``):
``geometry_msgs/msg/PoseStamped``, ``geometry_msgs/msg/Pose2D`` or ``nav_msgs/msg/Odometry``;
optionally one topic per robot its parent (``--parent-topics``, default ``/robot_{id}/parent``):
``std_msgs/msg/Int32`` or ``Int64``, ``-1`` meaning none.  Time: a message's header stamp where
its type has one (``time="header"``, the default: the instant the pose was measured), else its
log time; ``time="log"`` takes log times throughout.  Either way each topic's times must
increase; topics may interleave in any order.

The bag readers are an optional extra (``pip install 'swarmproof[ros]'``); without it, reading a
bag is a usage error that names the install command.  Every malformed input is an
:class:`~swarmproof.models.errors.InputFileError` naming the file, the topic or line, the
message index and the field.

Examples
--------
>>> import os, tempfile
>>> d = tempfile.mkdtemp(); p = os.path.join(d, "run.csv")
>>> _ = open(p, "w").write("t,id,x,y,theta,parent\\n0,1,0,0,0,\\n0,2,1,0,0,1\\n0.1,1,0,0.1,0,\\n0.1,2,1,0.1,0,1\\n")
>>> log = read_log(p)
>>> log.format, sorted(log.robots), log.robots[2].t.tolist(), log.parents[2].parent.tolist()
('csv', [1, 2], [0, 100000000], [1, 1])
"""

from __future__ import annotations

import csv
import io
import math
import os
import re
import shutil
import tempfile
from array import array
from dataclasses import dataclass, field
from typing import Iterable, Mapping

import numpy as np

from .errors import InputFileError, UsageError
from .fileio import _umask, atomic_write_bytes, atomic_write_text

__all__ = ["trace_period_ns", "RobotSamples", "ParentSamples", "RecordedLog", "read_log", "log_format", "topic_regex",
           "POSE_TYPES", "PARENT_TYPES", "STATE_TYPES", "DEFAULT_POSE_TOPICS", "DEFAULT_PARENT_TOPICS",
           "DEFAULT_STATE_TOPICS", "StateSamples", "INSTALL_ROS",
           "write_log", "EXPORT_FORMATS", "MAX_SAMPLES", "MAX_TIME_S", "MAX_COORDINATE", "MAX_ID", "yaw_of", "quaternion_of"]

#: The install command of the optional bag readers and writers.
INSTALL_ROS = "pip install 'swarmproof[ros]'  (rosbags, mcap, mcap-ros2-support)"
DEFAULT_POSE_TOPICS = "/robot_{id}/pose"
DEFAULT_PARENT_TOPICS = "/robot_{id}/parent"
DEFAULT_STATE_TOPICS = "/robot_{id}/state"
POSE_TYPES = ("geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/Pose2D", "nav_msgs/msg/Odometry")
PARENT_TYPES = ("std_msgs/msg/Int32", "std_msgs/msg/Int64")
STATE_TYPES = ("std_msgs/msg/String",)
#: Largest |t| in seconds (nanoseconds must fit int64: epoch times of 2026 are 1.8e9 s), largest
#: |x|, |y|, |theta|, largest robot id.
MAX_TIME_S = 4.0e9
MAX_COORDINATE = 1.0e9
MAX_ID = 2**31 - 1
#: Samples held at most (poses and parents together, 40 bytes each: 2 GB); past it, exit 2.
MAX_SAMPLES = 50_000_000
NS = 1_000_000_000
_CSV_REQUIRED = ("t", "id", "x", "y", "theta")


@dataclass
class RobotSamples:
    """One robot's pose samples: ``t`` (int64 nanoseconds, increasing), ``xyt`` (m x 3: x, y,
    theta in radians), where they came from (a topic, or ``csv``) and which time (``header``,
    ``log`` or ``csv``)."""

    id: int
    t: np.ndarray
    xyt: np.ndarray
    source: str
    time_source: str


@dataclass
class ParentSamples:
    """One robot's parent samples: ``t`` (int64 ns, increasing) and ``parent`` (int64; -1 none)."""

    id: int
    t: np.ndarray
    parent: np.ndarray
    source: str


@dataclass
class StateSamples:
    """One robot's controller states as logged: ``t`` (int64 ns, increasing) and ``values`` (the
    states in the trace's JSON form turned back into tuples, :func:`~swarmproof.models.trace.from_jsonable`)."""

    id: int
    t: np.ndarray
    values: list
    source: str


@dataclass
class RecordedLog:
    """A recorded run as samples: ``robots`` id -> :class:`RobotSamples`, ``parents`` id ->
    :class:`ParentSamples` (None when the log has no parent links), the ``format``
    (``csv``, ``mcap``, ``rosbag2-sqlite3``, ``rosbag2-mcap``) and notes for the report
    (ignored columns, topics that matched nothing)."""

    path: str
    format: str
    robots: dict
    parents: dict | None
    notes: list = field(default_factory=list)
    states: dict | None = None

    @property
    def samples(self) -> int:
        return int(sum(len(r.t) for r in self.robots.values()))


# ----------------------------------------------------------------------------
# angles
# ----------------------------------------------------------------------------

def yaw_of(qx: float, qy: float, qz: float, qw: float) -> float:
    """The heading (yaw, radians in (-pi, pi]) of a unit quaternion.

    >>> round(yaw_of(*quaternion_of(2.0)), 12)
    2.0
    """
    return math.atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))


def quaternion_of(theta: float) -> tuple[float, float, float, float]:
    """The unit quaternion ``(x, y, z, w)`` of a rotation by ``theta`` about z."""
    return 0.0, 0.0, math.sin(theta / 2.0), math.cos(theta / 2.0)


# ----------------------------------------------------------------------------
# which format
# ----------------------------------------------------------------------------

def log_format(path: str) -> str:
    """``csv``, ``mcap`` or ``rosbag2`` for a path; anything else is a usage error."""
    p = str(path)
    if os.path.isdir(p):
        if os.path.isfile(os.path.join(p, "metadata.yaml")):
            return "rosbag2"
        storage = [f for f in sorted(os.listdir(p)) if f.endswith((".db3", ".mcap"))]
        if storage:
            raise InputFileError(f"log={p!r} holds {storage[0]!r} but no metadata.yaml: a bag whose recorder "
                                 "was stopped before it wrote it", file=p,
                                 fix=f"rebuild metadata.yaml with `ros2 bag reindex {p}`, or give "
                                     f"{os.path.join(p, storage[0])!r} if it is an MCAP file")
        raise InputFileError(f"log={p!r} is a folder without metadata.yaml, not a rosbag2 bag", file=p,
                             fix="give a rosbag2 bag's folder (it holds metadata.yaml), an .mcap file or a .csv file")
    if not os.path.exists(p):
        raise InputFileError(f"log={p!r} does not exist", file=p, fix="check the path")
    low = p.lower()
    if low.endswith(".csv"):
        return "csv"
    if low.endswith(".mcap"):
        return "mcap"
    if low.endswith(".db3"):
        folder = os.path.dirname(p) or "."
        has_meta = os.path.isfile(os.path.join(folder, "metadata.yaml"))
        raise InputFileError(f"log={p!r} is the database inside a rosbag2 bag", file=p,
                             fix=f"give the bag's folder: {folder!r}" if has_meta else
                                 f"its folder has no metadata.yaml: rebuild it with `ros2 bag reindex {folder}`, then "
                                 "give the folder")
    raise InputFileError(f"log={p!r}: the suffix {os.path.splitext(p)[1]!r} is not a log format swarmproof reads",
                         file=p, fix="give a .csv file, an .mcap file or a rosbag2 bag's folder")


def topic_regex(pattern: str, option: str = "--topics") -> "re.Pattern":
    """The regular expression of a topic pattern with one ``{id}`` (the robot's integer id).

    >>> topic_regex("/robot_{id}/pose").match("/robot_12/pose").group("id")
    '12'
    >>> topic_regex("/pose")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: --topics='/pose' has no {id}; fix: name where the robot's id stands, e.g. --topics '/robot_{id}/pose'
    """
    if not isinstance(pattern, str) or pattern.count("{id}") != 1:
        raise UsageError(f"{option}={pattern!r} has no {{id}}" if "{id}" not in str(pattern)
                         else f"{option}={pattern!r} has {{id}} more than once",
                         fix="name where the robot's id stands, e.g. --topics '/robot_{id}/pose'")
    head, _, tail = pattern.partition("{id}")
    return re.compile("^" + re.escape(head) + r"(?P<id>\d+)" + re.escape(tail) + "$")


def _ros_import(what: str, path: str):
    raise UsageError(f"reading or writing {what} needs the optional extra that is not installed (log={path!r})",
                     fix=INSTALL_ROS)


# ----------------------------------------------------------------------------
# collecting samples
# ----------------------------------------------------------------------------

class _Collector:
    """Samples of one stream (a robot's topic or CSV rows), checked as they come.  Held compactly:
    times in an ``array('q')`` (a list once one does not fit in int64, as before: making the numpy
    array then fails), poses as flat doubles ``x, y, theta`` (``width`` 3), parents as a list of
    ints; where the previous sample came from is kept for the error of the next one."""

    __slots__ = ("rid", "source", "time_source", "path", "kind", "t", "v", "last", "where", "width")

    def __init__(self, rid: int, source: str, time_source: str, path: str, kind: str, width: int = 1) -> None:
        self.rid, self.source, self.time_source, self.path, self.kind = rid, source, time_source, path, kind
        self.width = width
        self.t = array("q")
        self.v = array("d") if width == 3 else []
        self.last = None           # the previous sample's time
        self.where = None          # where it came from: a CSV line, (topic, index), or a text

    def add(self, t_ns: int, value, where, line: int | None = None) -> None:
        last = self.last
        if last is not None and t_ns <= last:
            what = "repeats" if t_ns == last else "is earlier than"
            raise InputFileError(
                ("" if line is not None else f"{_where_text(where)}: ") +
                f"time t={t_ns / NS!r} s {what} the previous sample of robot {self.rid} "
                f"({last / NS!r} s, {_where_text(self.where)}); times must increase within a robot's "
                f"{'rows' if self.kind == 'csv' else 'topic'} ({self.time_source} time)",
                file=self.path, line=line,
                fix="sort the log by time (rows of different robots may interleave)" if self.kind == "csv" else
                    "record with increasing stamps, or judge by log time (--time log) if the header stamps are wrong")
        try:
            self.t.append(t_ns)
        except OverflowError:      # past int64: kept as a Python int (as before; the arrays cannot hold it)
            self.t = list(self.t)
            self.t.append(t_ns)
        if self.width == 3:
            self.v.extend(value)
        else:
            self.v.append(value)
        self.last = t_ns
        self.where = where


def _where_text(where) -> str:
    """``line 12`` for a CSV line number, ``topic '/robot_1/pose' message 3`` for ``(topic, index)``."""
    if isinstance(where, int):
        return f"line {where}"
    if isinstance(where, tuple):
        return f"topic {where[0]!r} message {where[1]}"
    return str(where)


def _finite(values: Mapping[str, float], where: str, path: str, line: int | None = None) -> None:
    """A non-finite number, or one past the magnitudes a log may hold (:data:`MAX_TIME_S`,
    :data:`MAX_COORDINATE`), is an error naming its field (``where`` only when no line says it)."""
    for name, val in values.items():
        bound = MAX_TIME_S if name == "t" else MAX_COORDINATE
        if not math.isfinite(val) or abs(val) > bound:
            said = "is not a finite number" if not math.isfinite(val) else f"is beyond +-{bound:g}"
            fix = ("drop or repair the sample (poses must be finite)" if not math.isfinite(val) else
                   "write t in seconds (not nanoseconds)" if name == "t" else
                   "write positions in metres and headings in radians")
            raise InputFileError(("" if line is not None else f"{where}: ") + f"{name}={val!r} {said}", file=path,
                                 line=line, field=name, fix=fix)


def _robots_from(collectors: Mapping[int, _Collector]) -> dict:
    out = {}
    for rid in sorted(collectors):
        c = collectors[rid]
        out[rid] = RobotSamples(rid, np.array(c.t, dtype=np.int64),
                                np.array(c.v, dtype=np.float64).reshape(-1, 3), c.source, c.time_source)
        c.t = c.v = None           # the collector's copy goes as the arrays are made
    return out


def _parents_from(collectors: Mapping[int, _Collector]) -> dict:
    out = {}
    for rid, c in sorted(collectors.items()):
        out[rid] = ParentSamples(rid, np.array(c.t, dtype=np.int64), np.asarray(c.v, dtype=np.int64), c.source)
        c.t = c.v = None
    return out


def _states_from(collectors: Mapping[int, _Collector]) -> dict:
    out = {}
    for rid, c in sorted(collectors.items()):
        out[rid] = StateSamples(rid, np.array(c.t, dtype=np.int64), list(c.v), c.source)
        c.t = c.v = None
    return out


def _parse_state(text, where: str, path: str, line: int | None, fieldname: str):
    """A logged controller state: JSON text in the trace's form (``[["parent", 3], ...]`` or an
    object), turned back into tuples as a loaded trace's states are."""
    import json

    from .trace import from_jsonable

    try:
        return from_jsonable(json.loads(text))
    except (TypeError, ValueError) as exc:
        raise InputFileError(("" if line is not None else f"{where}: ") + f"the state is not JSON ({_one_line(exc)})",
                             file=path, line=line, field=fieldname,
                             fix="log the controller state as JSON text, e.g. [[\"parent\", 3], [\"stable\", true]]") from None


def _check_size(count: int, path: str) -> None:
    if count > MAX_SAMPLES:
        raise InputFileError(f"the log holds more than {MAX_SAMPLES} samples (max_samples={MAX_SAMPLES})", file=path,
                             fix="judge a part of the log (split it by time), or downsample it")


# ----------------------------------------------------------------------------
# CSV
# ----------------------------------------------------------------------------

def _csv_columns(header: list, path: str, notes: list):
    """The columns of a CSV's header row: ``(required name -> index, parent index or None, state
    index or None, the names)``; a missing or repeated column is an error, others are noted."""
    if len(header) == 1 and ";" in header[0]:
        raise InputFileError(f"the header row {header[0]!r} is separated by ';'", file=path, line=1,
                             fix="separate the columns with commas (t,id,x,y,theta[,parent])")
    names = [h.strip().lower() for h in header]
    missing = [c for c in _CSV_REQUIRED if c not in names]
    if missing:
        raise InputFileError(f"the header row {header!r} lacks the column {missing[0]!r}", file=path, line=1,
                             field=missing[0], fix="name the columns t,id,x,y,theta (and optionally parent, state)")
    known = _CSV_REQUIRED + ("parent", "state")
    dup = sorted({n for n in names if names.count(n) > 1 and n in known})
    if dup:
        raise InputFileError(f"the header row names the column {dup[0]!r} twice", file=path, line=1, field=dup[0],
                             fix="keep one column of each name")
    ignored = [h for h in header if h.strip().lower() not in known]
    if ignored:
        notes.append(f"CSV columns ignored: {ignored}")
    return ({n: names.index(n) for n in _CSV_REQUIRED}, names.index("parent") if "parent" in names else None,
            names.index("state") if "state" in names else None, names)


def _read_csv(path: str, progress=None) -> RecordedLog:
    poses: dict[int, _Collector] = {}
    parents: dict[int, _Collector] = {}
    notes = []
    try:
        fh = open(path, newline="", encoding="utf-8-sig")     # a spreadsheet's byte-order mark is not a column
    except OSError as exc:
        raise InputFileError(f"log={path!r} cannot be opened ({exc.strerror})", file=path, fix="check the path") from None
    count = 0
    with fh:
        reader = csv.reader(fh)
        try:
            header = next(reader, None)
        except (csv.Error, UnicodeDecodeError) as exc:
            raise InputFileError(f"the CSV cannot be read ({exc})", file=path, line=1,
                                 fix="write UTF-8 text with a header row t,id,x,y,theta[,parent]") from None
        if header is None:
            raise InputFileError("the log is empty (no header row, no samples)", file=path, line=1,
                                 fix="write a header row t,id,x,y,theta[,parent] and one row per pose sample")
        col, pcol, scol, names = _csv_columns(header, path, notes)
        states: dict[int, _Collector] = {}
        width = len(names)
        ti, ii, xi, yi, hi = (col[c] for c in _CSV_REQUIRED)
        line = 1
        try:
            for row in reader:
                line += 1
                if len(row) != width:
                    if not row or (len(row) == 1 and not row[0].strip()):
                        continue
                    raise InputFileError(f"the row has {len(row)} fields, the header {width}", file=path, line=line,
                                         fix="give every row the header's columns")
                try:
                    t = float(row[ti]); x = float(row[xi]); y = float(row[yi]); th = float(row[hi])
                except ValueError:
                    bad = next(n for n, k in (("t", ti), ("x", xi), ("y", yi), ("theta", hi)) if not _is_float(row[k]))
                    raise InputFileError(f"{bad}={row[col[bad]]!r} is not a number", file=path, line=line, field=bad,
                                         fix="write a decimal number (t in seconds, theta in radians)") from None
                try:
                    rid = _integer(row[ii])
                except ValueError:
                    raise InputFileError(f"id={row[ii]!r} is not an integer", file=path, line=line, field="id",
                                         fix="name each robot by an integer id") from None
                if not (-MAX_TIME_S <= t <= MAX_TIME_S and -MAX_COORDINATE <= x <= MAX_COORDINATE
                        and -MAX_COORDINATE <= y <= MAX_COORDINATE and -MAX_COORDINATE <= th <= MAX_COORDINATE):
                    _finite({"t": t, "x": x, "y": y, "theta": th}, f"row {line}", path, line)   # NaN fails too
                if not 0 <= rid <= MAX_ID:
                    raise InputFileError(f"id={rid!r} is not in 0..{MAX_ID}", file=path, line=line, field="id",
                                         fix="name each robot by a non-negative integer id")
                t_ns = int(round(t * NS))
                c = poses.get(rid)
                if c is None:
                    c = poses[rid] = _Collector(rid, "csv", "csv", path, "csv", 3)
                c.add(t_ns, (x, y, th), line, line)
                if pcol is not None:
                    raw = row[pcol].strip()
                    try:
                        par = -1 if raw == "" else _integer(raw)
                    except ValueError:
                        raise InputFileError(f"parent={raw!r} is not an integer", file=path, line=line, field="parent",
                                             fix="give the parent's id, or leave it empty (or -1) for none") from None
                    if par > MAX_ID or par < -1:
                        raise InputFileError(f"parent={raw!r} is not in -1..{MAX_ID}", file=path, line=line,
                                             field="parent", fix="give the parent's id, or leave it empty (or -1)")
                    pc = parents.get(rid)
                    if pc is None:
                        pc = parents[rid] = _Collector(rid, "csv", "csv", path, "csv")
                    pc.add(t_ns, -1 if par < 0 else par, line, line)
                if scol is not None and row[scol].strip():
                    sc = states.get(rid)
                    if sc is None:
                        sc = states[rid] = _Collector(rid, "csv", "csv", path, "csv")
                    sc.add(t_ns, _parse_state(row[scol], "", path, line, "state"), line, line)
                count += 1
                if count > MAX_SAMPLES:
                    _check_size(count, path)
                if progress is not None and not count % 100_000:
                    progress(f"read {count} rows")
        except csv.Error as exc:
            raise InputFileError(f"the CSV cannot be read ({exc})", file=path, line=line + 1,
                                 fix="repair the row (quotes, separators)") from None
        except UnicodeDecodeError as exc:
            raise InputFileError(f"the CSV is not UTF-8 text ({exc.reason})", file=path, line=line + 1,
                                 fix="write the log as UTF-8 text") from None
    if not poses:
        raise InputFileError("the log is empty: a header row and no samples", file=path, line=2,
                             fix="write one row per pose sample: t,id,x,y,theta")
    if states and set(states) != set(poses):
        lacking = sorted(set(poses) - set(states))
        raise InputFileError(f"robot {lacking[0]} has no state in the 'state' column while robots "
                             f"{sorted(states)[:5]} have one", file=path, field="state",
                             fix="log every robot's state, or none (leave the column out)")
    return RecordedLog(path, "csv", _robots_from(poses), _parents_from(parents) if pcol is not None else None, notes,
                       _states_from(states) if states else None)


def _integer(text: str) -> int:
    """An id written as an integer, or as a float with nothing after the point (``3.0``: a spreadsheet's
    or pandas' way); anything else is a ``ValueError``."""
    try:
        return int(text)
    except ValueError:
        value = float(text)
        if not (math.isfinite(value) and value.is_integer()):
            raise
        return int(value)


def _guess_pattern(topics: Mapping[str, str]) -> str | None:
    """The ``--topics`` pattern most pose-typed topics share with their one number as ``{id}``
    (``/tb3_0/odom`` and ``/tb3_1/odom``: ``/tb3_{id}/odom``), or None."""
    counts: dict = {}
    for topic, msgtype in topics.items():
        if msgtype not in POSE_TYPES:
            continue
        for m in re.finditer(r"\d+", topic):         # each number of the name may be the id
            key = topic[:m.start()] + "{id}" + topic[m.end():]
            counts[key] = counts.get(key, 0) + 1
    best = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))
    return best[0][0] if best else None


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# ----------------------------------------------------------------------------
# bags: one decoded message -> a sample
# ----------------------------------------------------------------------------

def _stamp_ns(stamp) -> int:
    return int(stamp.sec) * NS + int(stamp.nanosec)


def _pose_sample(msgtype: str, msg, log_ns: int, time: str):
    """``(t_ns, (x, y, theta), time_source)`` of a pose message."""
    short = msgtype.replace("/msg/", "/")
    if short == "geometry_msgs/Pose2D":
        return log_ns, (float(msg.x), float(msg.y), float(msg.theta)), "log"
    if short == "geometry_msgs/PoseStamped":
        pose, header = msg.pose, msg.header
    else:      # nav_msgs/Odometry
        pose, header = msg.pose.pose, msg.header
    p, q = pose.position, pose.orientation
    t = _stamp_ns(header.stamp) if time == "header" else log_ns
    return t, (float(p.x), float(p.y), yaw_of(float(q.x), float(q.y), float(q.z), float(q.w))), \
        ("header" if time == "header" else "log")


def _pose_fields(msgtype: str, msg) -> dict:
    """The numbers of a pose message, by their field names (for the error of a non-finite one)."""
    short = msgtype.replace("/msg/", "/")
    if short == "geometry_msgs/Pose2D":
        return {"x": msg.x, "y": msg.y, "theta": msg.theta}
    pose = msg.pose if short == "geometry_msgs/PoseStamped" else msg.pose.pose
    pre = "pose" if short == "geometry_msgs/PoseStamped" else "pose.pose"
    p, q = pose.position, pose.orientation
    return {f"{pre}.position.x": p.x, f"{pre}.position.y": p.y, f"{pre}.orientation.x": q.x,
            f"{pre}.orientation.y": q.y, f"{pre}.orientation.z": q.z, f"{pre}.orientation.w": q.w}


def _pose_finite(msgtype: str, msg) -> bool:
    """Whether every number :func:`_pose_fields` names is finite and within :data:`MAX_COORDINATE`
    (the common case, without its dict; NaN fails every comparison)."""
    def ok(v) -> bool:
        return -MAX_COORDINATE <= v <= MAX_COORDINATE

    if msgtype == "geometry_msgs/msg/PoseStamped":
        pose = msg.pose
    elif msgtype == "nav_msgs/msg/Odometry":
        pose = msg.pose.pose
    else:
        return all(ok(v) for v in _pose_fields(msgtype, msg).values())
    p, q = pose.position, pose.orientation
    return ok(p.x) and ok(p.y) and ok(q.x) and ok(q.y) and ok(q.z) and ok(q.w)


class _Topics:
    """Which topics are robots' poses and parents, and their collectors."""

    def __init__(self, path: str, topics: Mapping[str, str], pose_pattern: str, parent_pattern: str | None,
                 parent_given: bool, time: str, progress=None, state_pattern: str | None = None,
                 state_given: bool = False) -> None:
        self.path, self.time, self.progress = path, time, progress
        if not topics:
            raise InputFileError("the log is empty: it has no topic (no message)", file=path,
                                 fix="record the robots' poses, one topic per robot")
        pose_re = topic_regex(pose_pattern, "--topics")
        head, _, tail = pose_pattern.partition("{id}")
        near = re.compile("^" + re.escape(head) + r"[^/]+" + re.escape(tail) + "$")
        self.ignored = sorted(t for t in topics if near.match(t) and not pose_re.match(t))
        parent_re = topic_regex(parent_pattern, "--parent-topics") if parent_pattern else None
        state_re = topic_regex(state_pattern, "--state-topics") if state_pattern else None
        self.kind: dict[str, tuple[str, int, str]] = {}      # topic -> (pose|parent, id, msgtype)
        seen: dict[tuple[str, int], str] = {}
        for topic, msgtype in sorted(topics.items()):
            for what, rx, types, opt in (("pose", pose_re, POSE_TYPES, "--topics"),
                                         ("parent", parent_re, PARENT_TYPES, "--parent-topics"),
                                         ("state", state_re, STATE_TYPES, "--state-topics")):
                m = rx.match(topic) if rx is not None else None
                if m is None:
                    continue
                if msgtype not in types:
                    raise InputFileError(f"topic {topic!r} (it matches {opt}) has the message type {msgtype!r}, "
                                         f"which swarmproof does not read as a {what}", file=path, field=topic,
                                         fix=f"record the {what} as one of {list(types)}, or narrow {opt}")
                rid = int(m.group("id"))
                if rid > MAX_ID:
                    raise InputFileError(f"topic {topic!r}: robot id {m.group('id')} is not in 0..{MAX_ID}", file=path,
                                         field=topic, fix="name each robot by a non-negative integer id")
                if (what, rid) in seen:
                    raise InputFileError(f"robot id {rid} has two {what} topics: {seen[(what, rid)]!r} and {topic!r}",
                                         file=path, field=topic, fix=f"keep one {what} topic per robot id (duplicate robot ids)")
                seen[(what, rid)] = topic
                self.kind[topic] = (what, rid, msgtype)
        self.poses = {rid: _Collector(rid, t, "?", path, "topic", 3) for (w, rid), t in seen.items() if w == "pose"}
        self.parents = {rid: _Collector(rid, t, "log", path, "topic") for (w, rid), t in seen.items() if w == "parent"}
        self.states = {rid: _Collector(rid, t, "log", path, "topic") for (w, rid), t in seen.items() if w == "state"}
        if not self.poses:
            guess = _guess_pattern(topics)
            raise InputFileError(f"no topic matches --topics={pose_pattern!r}; the log's topics: "
                                 f"{sorted(topics)[:20] or 'none'}", file=path, field="--topics",
                                 fix=(f"give the pattern of the robots' pose topics: --topics '{guess}' fits this log"
                                      if guess else "give the pattern of the robots' pose topics, e.g. --topics "
                                                    "'/robot_{id}/pose'"))
        for what, got, pattern, given, default in (("parent", self.parents, parent_pattern, parent_given,
                                                     DEFAULT_PARENT_TOPICS),
                                                    ("state", self.states, state_pattern, state_given,
                                                     DEFAULT_STATE_TOPICS)):
            if given and pattern and not got:
                raise InputFileError(f"no topic matches --{what}-topics={pattern!r}; the log's topics: "
                                     f"{sorted(topics)}", file=path, field=f"--{what}-topics",
                                     fix=f"give the pattern of the {what} topics, or leave --{what}-topics out")
            orphans = sorted(set(got) - set(self.poses))
            if orphans:
                raise InputFileError(f"robot {orphans[0]} has a {what} topic {got[orphans[0]].source!r} but no "
                                     "pose topic", file=path, field=got[orphans[0]].source,
                                     fix="record every robot's pose, or check --topics")
            lacking = sorted(set(self.poses) - set(got)) if got else []
            if lacking:
                raise InputFileError(f"robot {lacking[0]} has no {what} topic while robots "
                                     f"{sorted(got)[:5]} have one", file=path,
                                     field=(pattern or default).replace("{id}", str(lacking[0])),
                                     fix=f"record every robot's {what}" + (" (-1 for none)" if what == "parent" else "")
                                         + ", or none at all")
        self.index: dict[str, int] = {}
        self.count = 0

    def wanted(self) -> list:
        return sorted(self.kind)

    def add(self, topic: str, msg, log_ns: int) -> None:
        what, rid, msgtype = self.kind[topic]
        k = self.index.get(topic, 0)
        self.index[topic] = k + 1
        where = (topic, k)         # formatted only for an error (_where_text)
        if what == "pose":
            t, xyt, source = _pose_sample(msgtype, msg, log_ns, self.time)
            if not _pose_finite(msgtype, msg):
                _finite(_pose_fields(msgtype, msg), _where_text(where), self.path)
            c = self.poses[rid]
            c.time_source = source
            c.add(t, xyt, where)
        elif what == "parent":
            val = int(msg.data)
            self.parents[rid].add(log_ns, -1 if val < 0 else val, where)
        else:
            self.states[rid].add(log_ns, _parse_state(msg.data, _where_text(where), self.path, None,
                                                      f"{topic}[{k}].data"), where)
        self.count += 1
        if self.count > MAX_SAMPLES:
            _check_size(self.count, self.path)
        if self.progress is not None and not self.count % 50_000:
            self.progress(f"decoded {self.count} messages")

    def log(self, fmt: str) -> RecordedLog:
        empty = sorted(r for r, c in self.poses.items() if not c.t)
        if len(empty) == len(self.poses):
            raise InputFileError("the log is empty: its pose topics hold no message", file=self.path,
                                 field=self.poses[empty[0]].source, fix="record the robots' poses")
        if empty:
            raise InputFileError(f"robot {empty[0]}'s pose topic {self.poses[empty[0]].source!r} holds no message",
                                 file=self.path, field=self.poses[empty[0]].source,
                                 fix="record every robot's pose, or narrow --topics to the robots that ran")
        notes = [f"topics ignored: their robot id is not a non-negative integer: {self.ignored[:10]}"] \
            if self.ignored else []
        return RecordedLog(self.path, fmt, _robots_from(self.poses),
                           _parents_from(self.parents) if self.parents else None, notes,
                           _states_from(self.states) if self.states else None)


def _read_rosbag2(path: str, pose_pattern: str, parent_pattern: str | None, parent_given: bool, time: str,
                  progress=None, states=(None, False)):
    try:
        from rosbags.rosbag2 import Reader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        _ros_import("a rosbag2 bag", path)
    try:
        reader = Reader(path)
        reader.open()
    except Exception as exc:  # noqa: BLE001 - the library's error names what is wrong with the bag
        raise InputFileError(f"the rosbag2 bag cannot be opened ({type(exc).__name__}: {_one_line(exc)})", file=path,
                             fix="check that the bag is complete (metadata.yaml and its storage files)") from None
    try:
        storage = "mcap" if any(f.endswith(".mcap") for f in os.listdir(path)) else "sqlite3"
        topics = {c.topic: c.msgtype for c in reader.connections}
        sel = _Topics(path, topics, pose_pattern, parent_pattern, parent_given, time, progress, *states)
        typestore = get_typestore(Stores.ROS2_HUMBLE)
        conns = [c for c in reader.connections if c.topic in sel.kind]
        for c in conns:
            typestore.register(_msgdefs_of(c, typestore))
        try:
            for conn, log_ns, raw in reader.messages(connections=conns):
                msg = _decode(typestore, raw, conn.msgtype, path, conn.topic, sel.index.get(conn.topic, 0))
                sel.add(conn.topic, msg, int(log_ns))
        except InputFileError:
            raise
        except Exception as exc:  # noqa: BLE001 - a truncated or corrupt storage file
            raise InputFileError(f"the rosbag2 bag cannot be read past message {sum(sel.index.values())} "
                                 f"({type(exc).__name__}: {_one_line(exc)})", file=path,
                                 fix="the bag is truncated or corrupt: record it again, or repair it (ros2 bag reindex)") from None
        _check_complete(path, storage, conns, sel)
        return sel.log(f"rosbag2-{storage}")
    finally:
        try:
            reader.close()
        except Exception:  # noqa: BLE001
            pass


def _check_complete(path: str, storage: str, conns, sel) -> None:
    """A bag whose storage lost bytes may still read (SQLite fills a cut page with zeros): the
    messages read must be the ones metadata.yaml counts, and a sqlite3 file must pass SQLite's
    own ``PRAGMA quick_check``."""
    for c in conns:
        want, got = getattr(c, "msgcount", None), sel.index.get(c.topic, 0)
        if isinstance(want, int) and want != got:
            raise InputFileError(f"topic {c.topic!r}: {got} messages read, metadata.yaml counts {want}", file=path,
                                 field=c.topic, fix="the bag is truncated or corrupt: record it again, or repair it "
                                                    "(ros2 bag reindex)")
    if storage != "sqlite3":
        return
    import sqlite3

    for name in sorted(os.listdir(path)):
        if not name.endswith(".db3"):
            continue
        db = os.path.join(path, name)
        short = _sqlite_short(db)
        if short:
            raise InputFileError(f"the storage file {name!r} is cut short: {short}", file=path, field=name,
                                 fix="the bag is truncated: record it again, or recover what is left (ros2 bag reindex)")
        try:
            con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
            try:
                ok = con.execute("PRAGMA quick_check").fetchone()[0]
            finally:
                con.close()
        except sqlite3.Error as exc:
            ok = str(exc)
        if ok != "ok":
            raise InputFileError(f"the storage file {name!r} fails SQLite's integrity check ({_one_line(ok)})", file=path,
                                 field=name, fix="the bag is truncated or corrupt: record it again, or repair it "
                                                 "(ros2 bag reindex)")


def _sqlite_short(db: str) -> str | None:
    """Why a SQLite file is shorter than its header says (a cut file), or None.  The header's page
    size (offset 16) times its page count (offset 28, valid when offset 92 equals the change counter
    at 24) is the file's size; SQLite itself reads a missing tail as zeros."""
    try:
        with open(db, "rb") as fh:
            head = fh.read(100)
        size = os.path.getsize(db)
    except OSError as exc:
        return f"it cannot be read ({exc.strerror})"
    if len(head) < 100 or not head.startswith(b"SQLite format 3\x00"):
        return "it has no SQLite header"
    page = int.from_bytes(head[16:18], "big")
    page = 65536 if page == 1 else page
    count = int.from_bytes(head[28:32], "big")
    if head[92:96] == head[24:28] and count and size < page * count:
        return f"{size} bytes, its header says {page * count} ({count} pages of {page})"
    return None


def _msgdefs_of(conn, typestore) -> dict:
    """Types a connection declares that the typestore lacks (a user's bag may carry its own)."""
    if conn.msgtype in typestore.types:
        return {}
    from rosbags.typesys import get_types_from_msg

    msgdef = getattr(getattr(conn, "ext", None), "msgdef", None) or getattr(conn, "msgdef", None)
    text = getattr(msgdef, "data", msgdef)
    return get_types_from_msg(text, conn.msgtype) if isinstance(text, str) and text else {}


def _decode(typestore, raw, msgtype: str, path: str, topic: str, index: int):
    try:
        return typestore.deserialize_cdr(raw, msgtype)
    except Exception as exc:  # noqa: BLE001
        raise InputFileError(f"topic {topic!r} message {index} cannot be decoded as {msgtype} "
                             f"({type(exc).__name__}: {exc})", file=path, field=f"{topic}[{index}]",
                             fix="the message is corrupt, or its type is not the one the bag declares") from None


_MCAP_MAGIC = b"\x89MCAP0\r\n"
_MCAP_FIX = "the file is truncated or corrupt: record it again, or recover it with `mcap recover`"


def _mcap_records(fh, path: str, summary):
    """``(schema, channel, message)`` of every message: indexed reading where the file has a
    summary, else the records in file order (the summary is optional in MCAP)."""
    from mcap.reader import NonSeekingReader, make_reader

    if summary is not None:
        return make_reader(fh).iter_messages(log_time_order=True)
    fh.seek(0)
    return NonSeekingReader(fh).iter_messages()


def _mcap_topics(fh, path: str):
    """``(topics -> type, summary or None)``: from the summary, else from a pass over the records
    (a complete file without one); a file that does not end in MCAP's magic is truncated."""
    from mcap.reader import NonSeekingReader, make_reader

    summary = make_reader(fh).get_summary()
    if summary is not None:
        return {ch.topic: _ros2_type(summary.schemas[ch.schema_id].name if ch.schema_id in summary.schemas else "")
                for ch in summary.channels.values()}, summary
    fh.seek(-len(_MCAP_MAGIC), os.SEEK_END)
    if fh.read() != _MCAP_MAGIC:
        raise ValueError("it does not end with MCAP's magic bytes: truncated, or never closed")
    fh.seek(0)
    topics = {}
    for schema, channel, _ in NonSeekingReader(fh).iter_messages():
        topics.setdefault(channel.topic, _ros2_type(schema.name if schema is not None else ""))
    return topics, None


def _read_mcap(path: str, pose_pattern: str, parent_pattern: str | None, parent_given: bool, time: str,
               progress=None, states=(None, False)):
    try:
        from mcap_ros2.decoder import DecoderFactory
    except ImportError:
        _ros_import("an MCAP file", path)
    try:
        fh = open(path, "rb")
    except OSError as exc:
        raise InputFileError(f"log={path!r} cannot be opened ({exc.strerror})", file=path, fix="check the path") from None
    with fh:
        try:
            topics, summary = _mcap_topics(fh, path)
        except Exception as exc:  # noqa: BLE001 - the library's words for what is wrong with the file
            raise InputFileError(f"the MCAP file cannot be opened ({type(exc).__name__}: {_one_line(exc)})",
                                 file=path, fix=_MCAP_FIX) from None
        sel = _Topics(path, topics, pose_pattern, parent_pattern, parent_given, time, progress, *states)
        factory, decoders = DecoderFactory(), {}
        try:
            fh.seek(0)
            for schema, channel, message in _mcap_records(fh, path, summary):
                topic = channel.topic
                if topic not in sel.kind:
                    continue
                key = channel.schema_id
                dec = decoders.get(key)
                if dec is None:
                    dec = decoders[key] = factory.decoder_for(channel.message_encoding, schema)
                index = sel.index.get(topic, 0)
                if dec is None:
                    raise InputFileError(f"topic {topic!r} message {index}: encoding {channel.message_encoding!r} of "
                                         f"{schema.name if schema else 'no schema'} cannot be decoded", file=path,
                                         field=f"{topic}[{index}]", fix="record ROS 2 messages (cdr, ros2msg schemas)")
                try:
                    msg = dec(message.data)
                except Exception as exc:  # noqa: BLE001
                    raise InputFileError(f"topic {topic!r} message {index} cannot be decoded as {topics[topic]} "
                                         f"({type(exc).__name__}: {_one_line(exc)})", file=path,
                                         field=f"{topic}[{index}]",
                                         fix="the message is corrupt, or its type is not the one its schema declares") from None
                sel.add(topic, msg, int(message.log_time))
        except InputFileError:
            raise
        except Exception as exc:  # noqa: BLE001
            raise InputFileError(f"the MCAP file cannot be read past message {sum(sel.index.values())} "
                                 f"({type(exc).__name__}: {_one_line(exc)})", file=path, fix=_MCAP_FIX) from None
    return sel.log("mcap")


def _one_line(exc) -> str:
    """An exception's text on one line (a library's may span several)."""
    return " ".join(str(exc).split())[:300]


def _ros2_type(name: str) -> str:
    """``geometry_msgs/msg/PoseStamped`` for a schema named either way."""
    parts = name.split("/")
    return f"{parts[0]}/msg/{parts[1]}" if len(parts) == 2 else name


def read_log(path, *, topics: str | None = None, parent_topics: str | None = None, time: str | None = None,
             progress=None, state_topics: str | None = None) -> RecordedLog:
    """Read a recorded run (CSV, MCAP or a rosbag2 bag's folder) into samples.

    Parameters
    ----------
    path : str
    topics : str, optional
        The robots' pose topics, with ``{id}`` (bags only; default ``/robot_{id}/pose``).
    parent_topics : str, optional
        Their parent topics (bags only; default ``/robot_{id}/parent``, used when present).
    time : ``"header"`` (the default) or ``"log"``
        Which time a pose message is placed at (bags; CSV has its own ``t``, and refuses it).
    progress : callable, optional
        Called with a short text every 100,000 CSV rows or 50,000 bag messages (a terminal's status line).
    """
    if time not in (None, "header", "log"):
        raise UsageError(f"--time={time!r} is not one of ['header', 'log']",
                         fix="header: the messages' header stamps (where they have one); log: the log times")
    path = os.fspath(path)
    fmt = log_format(path)
    if fmt == "csv":
        if topics is not None or parent_topics is not None or time is not None or state_topics is not None:
            raise UsageError("--topics, --parent-topics, --state-topics and --time are a bag's; a CSV log has columns "
                             "and its own t",
                             fix="leave them out for a CSV log (columns t,id,x,y,theta[,parent])")
        return _read_csv(path, progress)
    pose = topics or DEFAULT_POSE_TOPICS
    parent = parent_topics or DEFAULT_PARENT_TOPICS
    reader = _read_mcap if fmt == "mcap" else _read_rosbag2
    return reader(path, pose, parent, parent_topics is not None, time or "header", progress,
                  (state_topics or DEFAULT_STATE_TOPICS, state_topics is not None))


# ----------------------------------------------------------------------------
# writing: our traces as logs (swarmproof export, simulate --export)
# ----------------------------------------------------------------------------

#: What ``write_log`` writes, by the destination's form.
EXPORT_FORMATS = {
    "csv": "a .csv file: t,id,x,y,theta,parent",
    "mcap": "an .mcap file with ROS 2 messages (Foxglove opens it)",
    "rosbag2": "a rosbag2 bag's folder (sqlite3 storage; --storage mcap for MCAP storage)",
}

#: ROS 2 message definitions (``ros2msg``) of what the exporter writes, for MCAP schemas.
_MSGDEFS = None


def _ros2_msgdefs() -> dict:
    global _MSGDEFS
    if _MSGDEFS is None:
        from rosbags.typesys import Stores, get_typestore

        ts = get_typestore(Stores.ROS2_HUMBLE)
        _MSGDEFS = {name: ts.generate_msgdef(name, ros_version=2)[0] for name in
                    ("geometry_msgs/msg/PoseStamped", "std_msgs/msg/Int32", "std_msgs/msg/String",
                     "visualization_msgs/msg/MarkerArray")}
    return _MSGDEFS


def export_format(dest: str, storage: str | None = None) -> str:
    """``csv``, ``mcap`` or ``rosbag2`` for an export destination."""
    low = str(dest).lower()
    if not str(dest).strip():
        raise UsageError(f"--to={dest!r} is empty", fix="name the log: run.csv, run.mcap, or a new folder for a bag")
    if low.endswith(".csv"):
        fmt = "csv"
    elif low.endswith(".mcap"):
        fmt = "mcap"
    elif os.path.splitext(low)[1] in ("", ".bag", ".rosbag2") or low.endswith(os.sep):
        fmt = "rosbag2"
    else:
        raise UsageError(f"--to={dest!r}: the suffix {os.path.splitext(dest)[1]!r} is not a log format",
                         fix="end it with .csv or .mcap, or give a folder name (no suffix) for a rosbag2 bag")
    if storage is not None and fmt != "rosbag2":
        raise UsageError(f"--storage={storage!r} applies to a rosbag2 bag; --to={dest!r} is {fmt}",
                         fix="leave --storage out, or give a folder name for a rosbag2 bag")
    if fmt == "rosbag2" and os.path.exists(dest):
        raise UsageError(f"--to={dest!r} exists already; a rosbag2 bag is written as a new folder",
                         fix="give a new folder name, or remove the old bag")
    return fmt


def write_log(samples: Iterable, dest: str, *, ids: Iterable[int], has_parent: bool, markers=(),
              storage: str | None = None, has_state: bool = False) -> str:
    """Write pose samples as a log; returns the path written.

    ``samples`` yields ``(t_ns, id, x, y, theta, parent)`` in time order (parent None: none), or
    ``(t_ns, id, x, y, theta, parent, state)`` with ``has_state`` (state: the controller state as
    JSON text, written to a CSV's ``state`` column or ``/robot_{id}/state``, ``std_msgs/msg/String``);
    ``markers`` are ``(t_ns, text, [(x, y), ...])``: a violation to show (MCAP and rosbag2 write
    them as a ``visualization_msgs/msg/MarkerArray`` on ``/swarmproof/violation``).  Nothing is
    half-written: a file goes through an atomic rename, a bag's folder too.
    """
    fmt = export_format(dest, storage)
    if fmt == "csv":
        out = io.StringIO()
        rows = csv.writer(out, lineterminator="\n")
        rows.writerow(["t", "id", "x", "y", "theta"] + (["parent"] if has_parent else []) + (["state"] if has_state else []))
        for t_ns, rid, x, y, th, par, *st in samples:
            row = [repr(t_ns / NS), str(rid), repr(float(x)), repr(float(y)), repr(float(th))]
            if has_parent:
                row.append("" if par is None else str(int(par)))
            if has_state:
                row.append(st[0] or "")
            rows.writerow(row)
        return atomic_write_text(dest, out.getvalue())
    try:
        if fmt == "mcap":
            import mcap_ros2.writer  # noqa: F401
        else:
            import rosbags.rosbag2  # noqa: F401
    except ImportError:
        _ros_import("an MCAP file" if fmt == "mcap" else "a rosbag2 bag", dest)
    ids = sorted(int(i) for i in ids)
    if fmt == "mcap":
        return _write_mcap(samples, dest, ids, has_parent, markers, has_state)
    return _write_rosbag2(samples, dest, ids, has_parent, markers, storage or "sqlite3", has_state)


def _pose_dict(t_ns: int, x: float, y: float, th: float) -> dict:
    qx, qy, qz, qw = quaternion_of(float(th))
    return {"header": {"stamp": {"sec": t_ns // NS, "nanosec": t_ns % NS}, "frame_id": "world"},
            "pose": {"position": {"x": float(x), "y": float(y), "z": 0.0},
                     "orientation": {"x": qx, "y": qy, "z": qz, "w": qw}}}


def _marker_dicts(t_ns: int, text: str, points) -> dict:
    stamp = {"sec": t_ns // NS, "nanosec": t_ns % NS}
    base = {"header": {"stamp": stamp, "frame_id": "world"}, "ns": "swarmproof", "action": 0,
            "pose": {"position": {"x": 0.0, "y": 0.0, "z": 0.0}, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}},
            "lifetime": {"sec": 0, "nanosec": 0}, "frame_locked": False, "colors": [], "texture_resource": "",
            "texture": {"header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}, "format": "", "data": []},
            "uv_coordinates": [], "mesh_file": {"filename": "", "data": []}, "mesh_use_embedded_materials": False}
    pts = [{"x": float(x), "y": float(y), "z": 0.0} for x, y in points]
    cx = sum(p["x"] for p in pts) / max(len(pts), 1)
    cy = sum(p["y"] for p in pts) / max(len(pts), 1)
    spheres = dict(base, id=0, type=7, scale={"x": 0.1, "y": 0.1, "z": 0.1},
                   color={"r": 1.0, "g": 0.0, "b": 0.0, "a": 1.0}, points=pts, text="")
    label = dict(base, id=1, type=9, scale={"x": 0.0, "y": 0.0, "z": 0.2},
                 color={"r": 1.0, "g": 0.0, "b": 0.0, "a": 1.0}, points=[], text=text,
                 pose={"position": {"x": cx, "y": cy, "z": 0.3}, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}})
    return {"markers": [spheres, label]}


def _write_mcap(samples, dest, ids, has_parent, markers, has_state=False) -> str:
    from mcap_ros2.writer import Writer

    defs = _ros2_msgdefs()
    buf = io.BytesIO()
    w = Writer(buf)
    pose_schema = w.register_msgdef("geometry_msgs/msg/PoseStamped", defs["geometry_msgs/msg/PoseStamped"])
    int_schema = w.register_msgdef("std_msgs/msg/Int32", defs["std_msgs/msg/Int32"]) if has_parent else None
    str_schema = w.register_msgdef("std_msgs/msg/String", defs["std_msgs/msg/String"]) if has_state else None
    seq = 0
    for t_ns, rid, x, y, th, par, *st in samples:
        if has_state and st and st[0] is not None:
            w.write_message(DEFAULT_STATE_TOPICS.format(id=rid), str_schema, {"data": st[0]},
                            log_time=t_ns, publish_time=t_ns, sequence=seq)
        w.write_message(DEFAULT_POSE_TOPICS.format(id=rid), pose_schema, _pose_dict(t_ns, x, y, th),
                        log_time=t_ns, publish_time=t_ns, sequence=seq)
        if has_parent:
            w.write_message(DEFAULT_PARENT_TOPICS.format(id=rid), int_schema, {"data": -1 if par is None else int(par)},
                            log_time=t_ns, publish_time=t_ns, sequence=seq)
        seq += 1
    if markers:
        m_schema = w.register_msgdef("visualization_msgs/msg/MarkerArray", defs["visualization_msgs/msg/MarkerArray"])
        for t_ns, text, points in markers:
            w.write_message("/swarmproof/violation", m_schema, _marker_dicts(t_ns, text, points),
                            log_time=t_ns, publish_time=t_ns)
    w.finish()
    return atomic_write_bytes(dest, buf.getvalue())


def _to_msg(typestore, typename: str, value):
    """A rosbags message object of ``typename`` from nested dicts."""
    cls = typestore.types[typename]
    fields = typestore.fielddefs[typename][1]
    kwargs = {}
    for name, desc in fields:
        v = value.get(name)
        kind, sub = desc
        if kind == 2:          # a message type
            kwargs[name] = _to_msg(typestore, sub if isinstance(sub, str) else sub[0], v or {})
        elif v is None:        # a field the dict leaves out: ROS 2's default value
            base = sub[0] if kind == 1 else None
            kwargs[name] = [] if kind in (3, 4) and sub[0][0] == 2 else \
                np.zeros(0, dtype=np.uint8) if kind in (3, 4) else "" if base == "string" else \
                False if base == "bool" else 0.0 if base in ("float32", "float64") else 0
        elif kind in (3, 4):   # arrays / sequences
            inner = sub[0]
            if inner[0] == 2:
                kwargs[name] = [_to_msg(typestore, inner[1], e) for e in v]
            else:
                base = inner[1][0] if isinstance(inner[1], tuple) else inner[1]
                kwargs[name] = list(v) if base == "string" else \
                    np.asarray(v, dtype=np.uint8 if base in ("uint8", "byte", "octet") else np.float64)
        else:
            kwargs[name] = v
    return cls(**kwargs)


def _write_rosbag2(samples, dest, ids, has_parent, markers, storage: str, has_state: bool = False) -> str:
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    if storage not in ("sqlite3", "mcap"):
        raise UsageError(f"--storage={storage!r} is not one of ['sqlite3', 'mcap']",
                         fix="sqlite3 (rosbag2's default) or mcap")
    ts = get_typestore(Stores.ROS2_HUMBLE)
    parent_dir = os.path.dirname(os.path.abspath(dest))
    tmp = tempfile.mkdtemp(prefix=".swarmproof-export-", dir=parent_dir)
    bag = os.path.join(tmp, os.path.basename(os.path.normpath(dest)))
    try:
        plugin = StoragePlugin.SQLITE3 if storage == "sqlite3" else StoragePlugin.MCAP
        with Writer(bag, version=8, storage_plugin=plugin) as w:
            pose_c = {rid: w.add_connection(DEFAULT_POSE_TOPICS.format(id=rid), "geometry_msgs/msg/PoseStamped",
                                            typestore=ts) for rid in ids}
            par_c = {rid: w.add_connection(DEFAULT_PARENT_TOPICS.format(id=rid), "std_msgs/msg/Int32", typestore=ts)
                     for rid in ids} if has_parent else {}
            st_c = {rid: w.add_connection(DEFAULT_STATE_TOPICS.format(id=rid), "std_msgs/msg/String", typestore=ts)
                    for rid in ids} if has_state else {}
            mark_c = w.add_connection("/swarmproof/violation", "visualization_msgs/msg/MarkerArray",
                                      typestore=ts) if markers else None
            Int32 = ts.types["std_msgs/msg/Int32"]
            String = ts.types["std_msgs/msg/String"]
            for t_ns, rid, x, y, th, par, *st in samples:
                if has_state and st and st[0] is not None:
                    w.write(st_c[rid], t_ns, ts.serialize_cdr(String(data=st[0]), "std_msgs/msg/String"))
                msg = _to_msg(ts, "geometry_msgs/msg/PoseStamped", _pose_dict(t_ns, x, y, th))
                w.write(pose_c[rid], t_ns, ts.serialize_cdr(msg, "geometry_msgs/msg/PoseStamped"))
                if has_parent:
                    w.write(par_c[rid], t_ns, ts.serialize_cdr(Int32(data=-1 if par is None else int(par)),
                                                               "std_msgs/msg/Int32"))
            for t_ns, text, points in markers:
                msg = _to_msg(ts, "visualization_msgs/msg/MarkerArray", _marker_dicts(t_ns, text, points))
                w.write(mark_c, t_ns, ts.serialize_cdr(msg, "visualization_msgs/msg/MarkerArray"))
        mask = _umask()
        for root, dirs, files in os.walk(bag):
            os.chmod(root, 0o777 & ~mask)
            for f in files:
                os.chmod(os.path.join(root, f), 0o666 & ~mask)
        os.rename(bag, dest)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return os.fspath(dest)


def _parent_of(state):
    """A trace state's ``parent`` (a tuple of pairs or a mapping), ``_MISSING`` when it has none."""
    if isinstance(state, dict):
        return state.get("parent", _MISSING)
    if isinstance(state, tuple):
        for item in state:
            if isinstance(item, tuple) and len(item) == 2 and item[0] == "parent":
                return item[1]
    return _MISSING


_MISSING = object()


def trace_period_ns(trace) -> int:
    """A run's step in nanoseconds (its params' ``dt``, 1 s without one): step ``s`` is logged at
    ``s`` times it."""
    dt = float(((trace.meta or {}).get("params") or {}).get("dt", 1.0) or 1.0)
    return max(1, int(round(dt * NS)))


def trace_samples(trace, *, states: bool = False) -> tuple[list, bool, int]:
    """A trace's poses as log samples ``(t_ns, id, x, y, theta, parent)`` in time order, whether
    its states name parents, and the period in ns (the run's ``dt``; step ``s`` is at ``s dt``).
    Robots absent at a step (crashed, not yet added) publish nothing there.  ``states``: each
    sample gains a seventh element, the robot's controller state as JSON text (the trace's JSON
    form) where it changed since the robot's last sample, else None (a state holds until it
    changes, as check-run reads it)."""
    import json

    from .trace import to_jsonable

    period = trace_period_ns(trace)
    has_parent = any(_parent_of(s) is not _MISSING for frame in trace.states[:1] + trace.states[-1:] for s in frame)
    ids = [int(i) for i in trace.ids]
    last: dict = {}
    out = []
    for i in range(len(trace.poses)):
        t_ns = trace.time_of(i) * period
        present = trace.present_at(i)
        for j, rid in enumerate(ids):
            if not present[j]:
                continue
            x, y, th = (float(v) for v in trace.poses[i, j])
            par = _parent_of(trace.states[i][j]) if has_parent else None
            sample = (t_ns, rid, x, y, th, None if par is _MISSING or par is None else int(par))
            if states:
                text = json.dumps(to_jsonable(trace.states[i][j]), separators=(",", ":"), sort_keys=True)
                sample += (None if last.get(rid) == text else text,)
                last[rid] = text
            out.append(sample)
    return out, has_parent, period


def has_states(trace) -> bool:
    """Whether a trace's robots have controller states worth logging (not all None)."""
    return any(s is not None for frame in trace.states[:1] for s in frame)
