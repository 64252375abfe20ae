"""``swarmproof check-run``: judge a recorded run (a real swarm's log) by swarmproof's properties.

Reads FILE -- a CSV (``t,id,x,y,theta[,parent]``), an MCAP file or a rosbag2 bag's folder
(sqlite3 or MCAP storage) with one pose topic per robot -- aligns the robots' samples on a
common clock (sample and hold, with a staleness bound) and judges connectivity at range phi,
tree links, collision, termination, and, given a target, formation, deadlock and oscillation,
with the same property objects as simulate and explore (docs/recorded-runs.md).  Every verdict
states the clock, the tolerance and how many instants were judged; an instant at which some
robot had no fresh sample is never counted as held.
Exit codes: 0 every property that decides held; 1 one was violated; 2 bad input (the file,
topic, message and field named); 3 one was inconclusive (unjudged instants, a vacuous run).
"""

from __future__ import annotations

from swarmproof.commands import emit_json, human

NAME = "check-run"
HELP = "judge a recorded run (ROS 2 bag, MCAP or CSV) by the same properties as simulated runs"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP

GIF_FRAMES = 120


def add_arguments(p) -> None:
    from swarmproof.checkers.recorded import DEFAULT_STALE_PERIODS, DEFAULT_STATIC_WINDOW_S
    from swarmproof.models.recorded_io import DEFAULT_PARENT_TOPICS, DEFAULT_POSE_TOPICS

    p.add_argument("file", metavar="FILE", help="the log: a .csv file, an .mcap file or a rosbag2 bag's folder")
    p.add_argument("--target", metavar="[KIND:]NAME|FILE",
                   help="the formation the swarm should reach (judges formation, deadlock, oscillation)")
    p.add_argument("--range", type=float, dest="range_", metavar="PHI",
                   help="communication range phi (default: the target lattice's range)")
    p.add_argument("--radius", type=float, metavar="R",
                   help="robot disc radius for collision (default: the algorithm's robot_radius, else 0.1)")
    p.add_argument("--property", action="append", default=None, metavar="P",
                   help="judge only these properties (repeatable; default: every one the log can give)")
    p.add_argument("--algorithm", metavar="REF",
                   help="judge as this algorithm claims (registry name or module:qualname): its claims decide the "
                        "exit code, its speed and lemma premise monitors are used")
    p.add_argument("--topics", metavar="PATTERN",
                   help=f"bags: the robots' pose topics, {{id}} the robot's id (default {DEFAULT_POSE_TOPICS!r})")
    p.add_argument("--parent-topics", metavar="PATTERN",
                   help=f"bags: the robots' parent topics, std_msgs/msg/Int32, -1 none (default "
                        f"{DEFAULT_PARENT_TOPICS!r}, when present)")
    p.add_argument("--state-topics", metavar="PATTERN",
                   help="bags: the robots' controller-state topics, std_msgs/msg/String with the state as JSON "
                        "(default '/robot_{id}/state', when present): premises, invariants and the algorithm's own "
                        "properties then apply")
    p.add_argument("--time", choices=("header", "log"), default=None,
                   help="bags: place a pose at its header stamp (default; log time for types without a header) "
                        "or at its log time")
    p.add_argument("--period", type=float, metavar="SECONDS",
                   help="the common clock's period (default: the log's median sampling interval)")
    p.add_argument("--stale", type=float, metavar="SECONDS",
                   help=f"a pose older than this is not evidence (default {DEFAULT_STALE_PERIODS:g} periods)")
    p.add_argument("--pos-tol", type=float, default=0.0, metavar="D",
                   help="position tolerance of the log's poses (default 0): widens the range margin (2D) and the "
                        "collision margin (D); a verdict the tolerance could overturn says so")
    p.add_argument("--range-margin", type=float, metavar="M", help="range margin (default 2 x --pos-tol)")
    p.add_argument("--collision-margin", type=float, metavar="M", help="collision radius margin (default --pos-tol)")
    p.add_argument("--static-window", type=float, default=DEFAULT_STATIC_WINDOW_S, metavar="SECONDS",
                   help=f"the swarm is at rest when no robot moved for this long (default {DEFAULT_STATIC_WINDOW_S:g} s)")
    p.add_argument("--v", type=float, metavar="V", help="maximum speed, for the lemma premises (default: the algorithm's)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--plot", metavar="PNG", help="draw the trajectories and the graph at the violation (or the end)")
    p.add_argument("--gif", metavar="GIF", help=f"animate the log (at most {GIF_FRAMES} frames)")


def report_document(rep, *, claims=None) -> dict:
    """The JSON document of a :class:`~swarmproof.checkers.recorded.RecordedReport`."""
    props = {}
    for name, r in rep.results.items():
        d = r.as_dict()
        d["tolerance_sensitive"] = rep.sensitive.get(name)
        d["judged_at"] = _judged_at(rep, name)
        d["decides"] = claims is None or claims.get(name) is not None
        props[name] = d
    log = rep.log
    return {
        "command": "check-run", "file": log.path, "format": log.format, "robots": len(log.robots),
        "ids": rep.ids, "samples": log.samples, "has_parents": log.parents is not None,
        "clock": {**rep.clock.as_dict(), "judged_instants": rep.judged_instants,
                  "alignment": "sample and hold (parents: held until changed)"},
        "gaps": [{k: g[k] for k in ("from_s", "to_s", "from_step", "to_step", "robots")} for g in rep.gaps[:50]],
        "gap_count": len(rep.gaps),
        "range": rep.phi, "radius": rep.radius, "tolerance": rep.tolerance, "at_rest": rep.static,
        "properties": props, "not_applicable": rep.not_applicable, "notes": list(log.notes),
        "verdict": overall(rep, claims), "exit_code": exit_code(rep, claims),
    }


def _judged_at(rep, name: str) -> dict:
    """The thresholds a property's verdict used, with their margins (stated in every verdict)."""
    from swarmproof.checkers.recorded import TOLERANCE_KNOBS

    knob = TOLERANCE_KNOBS.get(name, ("",))[0]
    if knob == "range":
        return {"range": rep.phi, "margin": rep.tolerance["range_margin"], "pos_tol": rep.tolerance["pos_tol"]}
    if knob == "radius":
        return {"radius": rep.radius, "margin": rep.tolerance["collision_margin"], "pos_tol": rep.tolerance["pos_tol"]}
    return {"pos_tol": rep.tolerance["pos_tol"]}


def overall(rep, claims=None) -> str:
    deciding = [r.status for n, r in rep.results.items() if claims is None or claims.get(n) is not None]
    if "violated" in deciding:
        return "violated"
    if "inconclusive" in deciding or not deciding:
        return "inconclusive"
    return "held"


def exit_code(rep, claims=None) -> int:
    from swarmproof.models.verdict import Verdict

    return Verdict(overall(rep, claims)).exit_code


def _lines(rep, doc, claims) -> list:
    from swarmproof.checkers.recorded import fmt_s

    c = doc["clock"]
    lines = [f"{doc['file']}: {doc['format']}, {doc['robots']} robots, {doc['samples']} pose samples"
             + ("" if doc["has_parents"] else ", no parent links"),
             f"clock: {c['time']} time, every {fmt_s(c['period_s'])} s from {fmt_s(c['start_s'])} s to {fmt_s(c['end_s'])} s "
             f"({c['instants']} instants, {c['judged_instants']} judged; a pose older than "
             + (f"{fmt_s(c['stale_s'])} s" if c["stale_min_s"] == c["stale_s"] else
                f"2.5 of its robot's own sampling intervals ({fmt_s(c['stale_min_s'])} s to {fmt_s(c['stale_s'])} s)")
             + " is stale; "
             "sample and hold)",
             f"range {doc['range']:g}, radius {doc['radius']:g}; tolerance: position {doc['tolerance']['pos_tol']:g}, "
             f"range margin {doc['tolerance']['range_margin']:g}, collision margin {doc['tolerance']['collision_margin']:g}"]
    for name, r in rep.results.items():
        mark = "" if claims is None or claims.get(name) is not None else "*"
        sens = "  [depends on the tolerance]" if rep.sensitive.get(name) else ""
        at = doc["properties"][name]["judged_at"]
        if "margin" in at and at["margin"]:
            sens += f"  ({'range' if 'range' in at else 'radius'} {at.get('range', at.get('radius')):g} +- {at['margin']:g})"
        lines.append(f"  {name}{mark}: {r.status.upper()}: {r.message}{sens}")
    for name, why in rep.not_applicable.items():
        lines.append(f"  {name}: not applicable ({why})")
    if claims is not None and any(claims.get(n) is None for n in rep.results):
        lines.append("  * not claimed by the algorithm: a finding, not judged")
    for note in doc["notes"]:
        lines.append(f"note: {note}")
    return lines


def run(args) -> int:
    from swarmproof.checkers.recorded import judge_log

    import sys

    from swarmproof.commands import StatusLine

    progress = StatusLine(sys.stderr, "check-run") if sys.stderr.isatty() else None   # a long log on a terminal
    try:
        rep, claims = judge_log(args.file, range=args.range_, target=args.target, algorithm=args.algorithm,
                                properties=args.property, topics=args.topics, parent_topics=args.parent_topics,
                                state_topics=args.state_topics,
                                time=args.time, radius=args.radius, pos_tol=args.pos_tol,
                                range_margin=args.range_margin, collision_margin=args.collision_margin,
                                period=args.period, stale=args.stale, v=args.v, static_window=args.static_window,
                                keep_frames=GIF_FRAMES if (args.plot or args.gif) else 0, progress=progress)
    finally:
        if progress is not None:
            progress.clear()
    doc = report_document(rep, claims=claims)
    if args.plot is not None:
        from swarmproof.checkers.recorded_plot import plot_recorded

        doc["plot"] = plot_recorded(rep, args.plot)
    if args.gif is not None:
        from swarmproof.checkers.recorded_plot import gif_recorded

        doc["gif"] = gif_recorded(rep, args.gif)
    if args.json:
        emit_json(doc)
    lines = _lines(rep, doc, claims)
    for key in ("plot", "gif"):
        if key in doc:
            lines.append(f"{key}: {doc[key]}")
    lines.append(f"result: {doc['verdict']} (exit {doc['exit_code']})")
    human(args, *lines)
    return doc["exit_code"]
