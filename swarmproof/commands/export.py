"""``swarmproof export``: write a trace or a counterexample as a log a ROS 2 user opens.

FILE is a swarmproof-trace/1 file (``simulate --trace``) or a swarmproof-counterexample/1 file
(``explore --out``; it is replayed first).  ``--to`` decides the format: ``.csv``
(``t,id,x,y,theta,parent``), ``.mcap`` (ROS 2 messages: Foxglove opens it), or a new folder name
for a rosbag2 bag (``--storage sqlite3``, the default, or ``mcap``; RViz and ``ros2 bag play``
read it).  Poses go on ``/robot_{id}/pose`` (``geometry_msgs/msg/PoseStamped``, frame
``world``), parents on ``/robot_{id}/parent`` (``std_msgs/msg/Int32``, -1 none), and a
counterexample's violation on ``/swarmproof/violation`` (``visualization_msgs/msg/MarkerArray``)
at its step.  Step ``s`` is at ``s * dt`` seconds.  ``swarmproof check-run`` reads every one of
these back (docs/recorded-runs.md).
Exit codes: 0 written; 2 bad input or a destination that exists.
"""

from __future__ import annotations

from swarmproof.commands import emit_json, human

NAME = "export"
HELP = "write a trace or counterexample as a CSV, MCAP or rosbag2 log (ROS 2 messages)"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def add_arguments(p) -> None:
    p.add_argument("file", metavar="TRACE_OR_COUNTEREXAMPLE",
                   help="a swarmproof-trace/1 file (.json or .npz) or a swarmproof-counterexample/1 file")
    p.add_argument("--to", required=True, metavar="FILE.csv|FILE.mcap|FOLDER",
                   help="the log to write: .csv, .mcap, or a new folder name (a rosbag2 bag)")
    p.add_argument("--storage", choices=("sqlite3", "mcap"), default=None,
                   help="a rosbag2 bag's storage (default sqlite3)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _load(path: str):
    """``(trace, markers, what)`` of a trace or counterexample file."""
    import json

    from swarmproof.models.counterexample import COUNTEREXAMPLE_FORMAT
    from swarmproof.models.trace import Trace

    low = str(path).lower()
    if not low.endswith((".json", ".npz")):
        from swarmproof.models.errors import UsageError

        raise UsageError(f"TRACE_OR_COUNTEREXAMPLE={str(path)!r} is not a trace or counterexample file (.json or .npz)",
                         fix="give a file of simulate --trace or explore --out (a log is read by check-run, not export)")
    head = None
    if not low.endswith(".npz"):
        try:
            with open(path, encoding="utf-8") as fh:
                head = json.load(fh).get("format")
        except (OSError, ValueError, AttributeError):
            head = None     # Trace.load / replay_file say what is wrong, naming the file
    if head == COUNTEREXAMPLE_FORMAT:
        from swarmproof.checkers.replay import replay_file

        rr = replay_file(path)
        trace = rr.result.trace
        markers = []
        if rr.reproduced and rr.step is not None:
            markers = [_marker(trace, rr)]
        return trace, markers, "counterexample"
    return Trace.load(path), [], "trace"


def marker_of(trace, step: int, text: str, robots=None):
    """``(t_ns, text, points)``: the robots ``robots`` (default: every present one) at ``step``."""
    from swarmproof.models.recorded_io import trace_period_ns

    f = trace.frame_of(int(step))
    if f is None:
        f = len(trace.poses) - 1
    ids = [int(i) for i in trace.ids]
    pres = trace.present_at(f)
    pick = [j for j, rid in enumerate(ids) if pres[j] and (robots is None or rid in robots)]
    points = [(float(trace.poses[f, j, 0]), float(trace.poses[f, j, 1])) for j in pick]
    return int(step) * trace_period_ns(trace), text, points


def _marker(trace, rr):
    w = rr.verdict.witness or {}
    robots = set(int(x) for x in (w.get("robots") or [])) | {int(w[k]) for k in ("child", "parent", "robot")
                                                              if isinstance(w.get(k), int)}
    import math

    from swarmproof.checkers.recorded import shown_at

    # at the step where the violation first shows (a broken link one step after the step it broke in)
    step = int(math.ceil(round(shown_at(rr.counterexample.property, w), 9)))
    return marker_of(trace, step, f"{rr.counterexample.property}: {rr.verdict.message}"[:200], robots or None)


def export_trace(trace, dest: str, *, markers=(), storage=None) -> str:
    """Write ``trace`` to ``dest`` (format by its form) with ``markers``; returns the path."""
    from swarmproof.models.recorded_io import has_states, trace_samples, write_log

    with_states = has_states(trace)
    samples, has_parent, _ = trace_samples(trace, states=with_states)
    return write_log(iter(samples), dest, ids=trace.ids, has_parent=has_parent, markers=markers, storage=storage,
                     has_state=with_states)


def run(args) -> int:
    from swarmproof.models.recorded_io import export_format

    fmt = export_format(args.to, args.storage)
    trace, markers, what = _load(args.file)
    path = export_trace(trace, args.to, markers=markers, storage=args.storage)
    doc = {"command": "export", "file": args.file, "kind": what, "to": path,
           "format": fmt if fmt != "rosbag2" else f"rosbag2-{args.storage or 'sqlite3'}",
           "robots": int(trace.n), "steps": int(trace.steps), "markers": len(markers)}
    if args.json:
        emit_json(doc)
    where = "" if not markers else (" (the violation is not marked: a CSV has no topic for markers)" if fmt == "csv"
                                    else f" (the violation marked on /swarmproof/violation at {markers[0][0] / 1e9:g} s)")
    human(args, f"{what} {args.file}: {trace.n} robots, {trace.steps} steps -> {doc['format']} {path}{where}")
    return 0
