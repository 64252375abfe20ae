"""``swarmproof simulate``: run a reference implementation and check what it claims.

Runs ALGORITHM (a registry name, :mod:`swarmproof.reference_impl.registry`)
from a random connected start of ``--robots`` robots (seeded; or
``--initial FILE``) toward a target -- ``--target [KIND:]NAME|FILE`` of any
kind (lattice, lines, shape, pattern; ``--lattice``, ``--shape`` and ``--pattern`` are
aliases fixing the kind) -- then checks the final formation against the
target (a lattice: 001 Def. 2), connectivity at every step (001 Lemma 11), the
spanning-tree links and termination, the robots' own completion detection at every
step when they have one (004 Sec. III-B: ``completion_sound``), and reports the target's
metrics (a lattice: 001 Sec. III-C / 000 Eq. 3).

Every property is reported; the exit code follows the ones the algorithm claims (its class's
``claims``), and a property it does not claim is marked ``*``: a finding, not judged.  A
property the algorithm cannot give what it needs for says "not applicable".
Exit codes: 0 the run ended (finished or static) and every claimed property held; 1 a claimed
property failed, or the algorithm crashed; 2 usage error or unreadable input; 3 the step cap
was reached first, or a claimed property is inconclusive.
"""

from __future__ import annotations

import math
import sys

from swarmproof.commands import add_tree_link_mode, emit_json, human
from swarmproof.models.errors import UsageError

NAME = "simulate"
HELP = "run a reference implementation from a random connected start and check the result"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP



def add_arguments(p) -> None:
    p.add_argument("algorithm", metavar="ALGORITHM",
                   help="registry name (e.g. song2016, song2014, example-gather) or module:qualname of your class")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--target", metavar="[KIND:]NAME|FILE",
                       help="the target: a bundled name (a kind prefix decides when two kinds bundle it, "
                            "e.g. lattice:hexagon), a lattice-graph/1 file or a target description file")
    which.add_argument("--lattice", metavar="NAME|FILE", help="a lattice target (--target lattice:NAME)")
    which.add_argument("--shape", metavar="NAME|FILE", help="a goal-set target (--target shape:NAME)")
    which.add_argument("--pattern", metavar="NAME|FILE",
                       help="a pattern target of the algorithm's own pattern kind: a repeating pattern "
                            "(--target pattern:NAME) or, for Lee & Chong 2008's algorithms, a line pattern (--target lines:NAME)")
    p.add_argument("--robots", type=int, metavar="N", help="number of robots (random connected start)")
    p.add_argument("--seed", type=int, required=True, metavar="S", help="seed of the start and of the run")
    p.add_argument("--range", type=float, dest="range_", metavar="PHI",
                   help="sensing/communication range phi (default: the lattice file's range)")
    p.add_argument("--max-steps", type=int, metavar="K", help="step cap (default: the algorithm's)")
    p.add_argument("--initial", metavar="FILE", help="start from a swarmproof-initial/1 file instead")
    p.add_argument("--v", type=float, metavar="V", help="maximum linear speed (default: the algorithm's, else 0.05)")
    p.add_argument("--omega", type=float, metavar="W",
                   help="maximum angular speed, rad per time (default: the algorithm's, else pi/4)")
    p.add_argument("--dt", type=float, metavar="DT", help="step length (default: the algorithm's, else 1)")
    p.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="algorithm parameter (Params.extra), repeatable; numbers are parsed")
    p.add_argument("--min-separation", type=float, metavar="D",
                   help="minimum separation of the random connected start of continuous robots (default "
                        "range/4); refused (exit 2) where no start would keep it: with --initial, for grid "
                        "robots (distinct waypoints, grid_spacing apart) and for an algorithm's own start "
                        "(wang2020's arena)")
    p.add_argument("--allow-violations", action="store_true",
                   help="run even when a paper assumption is broken (reported)")
    p.add_argument("--strict", action="store_true",
                   help="refuse a lattice file of yours that check-lattice does not pass at the range in use")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--plot", metavar="PNG", help="draw the final formation, tree and trajectories")
    p.add_argument("--trace", metavar="FILE", help="write the trace (.json or .npz)")
    p.add_argument("--export", metavar="FILE.csv|FILE.mcap|FOLDER",
                   help="write the run as a log: .csv, .mcap (ROS 2 messages) or a new rosbag2 bag's folder "
                        "(swarmproof export; check-run reads it back)")
    p.add_argument("--gif", metavar="GIF", help="write an animation of the run (every recorded step, at most "
                                               f"{GIF_FRAMES} frames)")
    p.add_argument("--then", action="append", default=[], metavar="PATTERN",
                   help="switch to PATTERN once the present one stands (repeatable, in order; --param then=...): "
                        "003's leechong-* a line pattern, e.g. --then circle; wang2020 a shape, scaled to "
                        "--robots and formed once the one before is detected complete (004 Fig. 9), e.g. "
                        "--target shape:letter-n --then shape:letter-u")
    p.add_argument("--fail", action="append", default=[], metavar="ROBOT@STEP",
                   help="robot ROBOT fails at step STEP (003's algorithms: an allocated ID or 'leader'; "
                        "repeatable: --param fail=...)")
    add_tree_link_mode(p)
    p.add_argument("--vectorised", action="store_true",
                   help="run the algorithm's vectorised path (wang2020: the same trace as the per-robot "
                        "reference, bit for bit, for the paper's plain model; anything else is refused)")
    p.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                   help="stop a run that has not returned after SECONDS of wall-clock time (a step of the "
                        "algorithm that never returns, a run too long to wait for): inconclusive, exit 3 "
                        "(default: no limit; the step cap bounds the run)")
    p.add_argument("--record-every", type=int, default=1, metavar="K",
                   help="keep every K-th step (and every event, and the last) in the trace; connectivity "
                        "and tree links are still judged on every step by streaming monitors (default 1)")


GIF_FRAMES = 120


def _extra_with_options(args, spec) -> dict:
    """``--param`` values, plus ``--then`` / ``--fail`` for the algorithms that take them (their class
    lists ``then`` / ``fail`` in ``options``: 003's leechong-*, and wang2020's ``then``); for any other
    algorithm they are a usage error."""
    extra = _parse_extra(getattr(args, "param", []) or [])
    takes = tuple(getattr(spec.factory, "options", ()) or ())
    for flag, key in (("--then", "then"), ("--fail", "fail")):
        values = getattr(args, key, None) or []
        if not values:
            continue
        if key not in takes:
            raise UsageError(f"{flag} {values[0]!r}: algorithm={spec.label!r} does not take {flag}",
                             fix="drop it (003's leechong-* algorithms switch patterns and take failures; "
                                 "wang2020 forms shapes one after another with --then)")
        extra[key] = ",".join(str(v) for v in values)
    return extra


def _parse_extra(items) -> dict:
    out = {}
    for item in items:
        key, sep, val = item.partition("=")
        if not sep or not key:
            raise UsageError(f"--param {item!r} must be KEY=VALUE", fix="e.g. --param d_s=0.5")
        try:
            v: object = int(val)
        except ValueError:
            try:
                v = float(val)
            except ValueError:
                v = {"true": True, "false": False}.get(val.lower(), val)
        out[key] = v
    return out


def _progress_printer(stream=None):
    """The step counter on a terminal (a :class:`~swarmproof.commands.StatusLine`, erased with
    ``.clear()`` before the report is printed), or None when ``stream`` (stderr) is not one."""
    from swarmproof.commands import StatusLine

    stream = sys.stderr if stream is None else stream
    if not stream.isatty():
        return None
    line = StatusLine(stream, "simulate")

    def show(step: int, cap: int) -> None:
        line(f"step {step}/{cap}")

    show.clear = line.clear
    return show


def _target(args, spec):
    """The target of ``--target`` (any kind), or of the alias that fixes its kind: ``--lattice``,
    ``--shape``, or ``--pattern`` (the algorithm's own kind of pattern: 003's line patterns, 002's
    repeating ones)."""
    from swarmproof.models.targets import resolve_target

    if args.target is not None:
        return resolve_target(args.target)
    option = next(k for k in ("lattice", "shape", "pattern") if getattr(args, k) is not None)
    # --pattern names the algorithm's own kind of pattern (003's line patterns, 002's repeating ones)
    kind = getattr(spec.factory, "pattern_kind", "pattern") if option == "pattern" else option
    return resolve_target(getattr(args, option), kind=kind)


def _check_arguments(args) -> None:
    """The numbers and output paths of the command line, checked before the run (a finished
    report is never lost to a bad path)."""
    from swarmproof.models.fileio import check_output_path

    if args.seed < 0:
        raise UsageError(f"--seed {args.seed!r} must be >= 0")
    if args.range_ is not None and not (math.isfinite(args.range_) and args.range_ > 0):
        raise UsageError(f"--range {args.range_!r} must be a finite number > 0")
    if args.max_steps is not None and args.max_steps < 0:
        raise UsageError(f"--max-steps {args.max_steps!r} must be >= 0")
    if args.timeout is not None and not (math.isfinite(args.timeout) and args.timeout > 0):
        raise UsageError(f"--timeout={args.timeout!r} must be a number of seconds > 0",
                         fix="e.g. --timeout 60, or leave it out for no limit")
    from swarmproof.checkers.watchdog import MAX_LIMIT_S
    if args.timeout is not None and args.timeout > MAX_LIMIT_S:
        raise UsageError(f"--timeout={args.timeout:g} is more than {MAX_LIMIT_S:g} seconds (about 115 days)",
                         fix="give fewer seconds, or leave it out for no limit")
    if args.record_every < 1:
        raise UsageError(f"--record-every {args.record_every!r} must be >= 1", fix="1 records every step")
    for option, value in (("--trace", args.trace), ("--plot", args.plot), ("--gif", args.gif)):
        if value is not None:            # checked before the run: a finished report is never lost
            check_output_path(value, option)
    from swarmproof.reference_impl.engine.parameters import check_motion_value

    for name in ("v", "omega", "dt"):
        val = getattr(args, name, None)
        if val is not None:
            check_motion_value(name, val)     # > 0, with the reason (a robot that cannot move: no run)


def _initial(args):
    """The start of ``--initial FILE`` (``--robots``, if given, must agree), or None for a seeded
    start of ``--robots`` robots."""
    from swarmproof.reference_impl import initial as initial_mod

    if args.initial is not None:
        init = initial_mod.from_file(args.initial)
        if args.robots is not None and args.robots != init.n:
            raise UsageError(f"--robots {args.robots} disagrees with {args.initial!r} ({init.n} robots)",
                             fix="drop --robots or make them agree")
        return init
    if args.robots is None:
        raise UsageError("--robots N is required without --initial", fix="e.g. --robots 10")
    if args.robots < 1:
        raise UsageError(f"--robots {args.robots!r} must be >= 1", fix="give the team size, e.g. --robots 10")
    return None


def _write_files(args, checked) -> None:
    """Write ``--trace``, ``--plot`` and ``--gif``, each path recorded in the JSON document."""
    doc, trace = checked.doc, checked.result.trace
    lattice = checked.lattice   # the target as run (an algorithm may scale a shape to --robots)
    if args.trace is not None:
        doc["trace"] = trace.save(args.trace)
    if getattr(args, "export", None) is not None:
        from swarmproof.commands.export import export_trace

        doc["export"] = export_trace(trace, args.export)
    if args.plot is not None:
        doc["plot"] = plot_run(trace, lattice, getattr(checked.satisfaction, "roles", None), args.plot, doc["range"])
    if args.gif is not None:
        from swarmproof.checkers.plotting import animate_trace

        doc["gif"] = animate_trace(trace, args.gif, title=f"{checked.algorithm.name} on {lattice.name}",
                                   max_frames=GIF_FRAMES)


def _report_lines(args, checked) -> list:
    """The human report of a checked run: what ran, each judgment, the figures, the files, then
    the result line of the exit code."""
    doc, result, sat, conn, links, term = (checked.doc, checked.result, checked.satisfaction,
                                           checked.connectivity, checked.tree_links, checked.termination)
    q = doc["fulfillment_ratio"]
    q_txt = "undefined (lattice not satisfied)" if q is None else f"{q:.4f}"
    kind = doc["target"]["kind"]
    claims, na = checked.claims, checked.not_applicable

    own = getattr(checked, "own", None) or {}

    def judged(prop: str, res) -> str:
        """``status - message``; ``not applicable - why`` (no verdict); ``*`` when not claimed."""
        if prop in na:
            return f"not applicable - {na[prop]}"
        if res is None:                 # an own property that does not apply
            return "not applicable"
        mark = "" if claims.get(prop) is not None else "*"
        return f"{res.status}{mark} - {res.message}"

    lines = [
        f"{checked.algorithm.name} on {checked.lattice.name}: {checked.initial.n} robots, seed {args.seed}, "
        f"range {doc['range']:g}",
        f"  run: {result.status} after {result.steps} steps (static from step {doc['execution_steps']})",
        f"  satisfies {kind}: {judged('formation', sat)}",
        f"  connectivity: {judged('connectivity', conn)}",
        f"  tree links: {judged('tree_links', links)}",
    ]
    if kind == "lattice":
        lines.append(f"  fulfillment ratio Q: {q_txt}")
    else:
        lines += [f"  {key}: {_fmt(val)}" for key, val in doc["metrics"].items()]
    lines.append(f"  total distance: {doc['total_distance']:.6g}, min separation: "
                 + ("n/a" if doc["min_separation"] is None else f"{doc['min_separation']:.6g}"))
    if term is not None:
        lines.append(f"  termination: {judged('termination', term)}")
    completion = getattr(checked, "completion_sound", None)
    if completion is not None:          # only algorithms whose robots detect completion
        lines.append(f"  completion detection: {judged('completion_sound', completion)}")
    prem = getattr(checked, "premises", None)
    transfer = prem is not None and prem.violated and bool(prem.witness.get("transfer"))
    if prem is not None:                # only algorithms that declare lemma premise monitors
        # a transfer failure decides the exit code whatever is claimed: no "*"
        lines.append(f"  lemma premises: {prem.status}{'' if transfer else '*'} - {prem.message}")
    for prop, res in own.items():       # the algorithm's own properties (e.g. song2016's tree_link_cases)
        lines.append(f"  {prop}: {judged(prop, res)}")
    if result.crash is not None:
        c = result.crash
        who = "the algorithm" if c["robot"] is None else f"robot {c['robot']}'s controller"
        lines.append(f"  crash: {who} raised {c['error']}: {c['message']} in step {c['step']} ({c['where']})")
    if result.broken_assumptions:
        lines.append(f"  broken assumptions: {', '.join(result.broken_assumptions)}")
    if args.trace is not None:
        lines.append(f"  trace: {doc['trace']}")
    if getattr(args, "export", None) is not None:
        lines.append(f"  log: {doc['export']} (swarmproof check-run {doc['export']} --range {doc['range']:g})")
    if args.plot is not None:
        lines.append(f"  plot: {doc['plot']}")
    if args.gif is not None:
        lines.append(f"  animation: {doc['gif']}")
    shown = {"formation": sat, "connectivity": conn, "tree_links": links, "termination": term,
             "completion_sound": completion, "premises": None if transfer else prem, **own}
    unclaimed = [p for p, r in shown.items() if r is not None and p not in na and claims.get(p) is None]
    if unclaimed:
        paper = getattr(checked.algorithm, "paper", None)
        lines.append(f"  * not claimed by {'the paper' if paper else 'the algorithm'}: reported, "
                     "not judged for the exit code")
    findings = [p for p in unclaimed if shown[p].violated]
    lines.append({0: "result: ok", 1: "result: the algorithm crashed (a finding)" if result.crash else
                  "result: a proof does not transfer to this run (every premise of a lemma held, its "
                  "conclusion did not)" if checked.exit_by_transfer else
                  "result: a claimed property failed",
                  3: "result: inconclusive (step cap reached)" if result.status == "step_cap" else
                  "result: inconclusive (a claimed property was not decided)"}[checked.exit_code]
                 + (f" (findings, not claimed: {', '.join(findings)})" if findings else ""))
    if checked.exit_code == 0 and doc.get("warnings"):   # never a bare "ok" toward a lattice with defects
        lines[-1] += " for the checks above, but the lattice has defects (see the warning on stderr)"
    return lines


def run(args) -> int:
    """Run ``swarmproof simulate``: check the command line, run and check the algorithm
    (:func:`~swarmproof.checkers.runs.run_and_check`), write the files asked for, then print the
    JSON document or the human report; returns the run's exit code."""
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.checkers.runs import run_and_check

    spec = resolve_algorithm(args.algorithm)  # unknown names fail first, listing the valid ones
    lattice = _target(args, spec)
    _check_arguments(args)
    init = _initial(args)
    from swarmproof.checkers.watchdog import Overstayed, time_limit

    progress = _progress_printer()
    try:
        with time_limit(args.timeout):
            checked = run_and_check(
                args.algorithm, lattice, seed=args.seed, robots=args.robots, initial=init, phi=args.range_,
                max_steps=args.max_steps, v=args.v, omega=args.omega, dt=args.dt,
                extra=_extra_with_options(args, spec), min_separation=args.min_separation,
                allow_violations=args.allow_violations, progress=progress, record_every=args.record_every,
                tree_link_mode=args.tree_link_mode,
                strict=args.strict, vectorised=args.vectorised, premises=True, own_properties=True)
    except Overstayed as exc:
        return _timed_out(args, exc)
    finally:
        if progress is not None:
            progress.clear()     # erase the step counter: the report starts on a clean line
    for w in checked.doc.get("warnings", ()):
        sys.stderr.write(f"swarmproof simulate: warning: {w}\n")
    _write_files(args, checked)
    if args.json:
        emit_json(checked.doc)
    else:
        human(args, *_report_lines(args, checked))
    return checked.exit_code


def _timed_out(args, exc) -> int:
    """``--timeout`` stopped the run before it returned: inconclusive (exit 3), nothing written."""
    from swarmproof.models.verdict import EXIT_INCONCLUSIVE

    msg = f"the run {exc}; raise --timeout, or look at that code: it may never return"
    if args.json:
        emit_json({"algorithm": args.algorithm, "robots": args.robots, "seed": args.seed, "status": "timeout",
                   "timeout": args.timeout, "where": exc.where, "message": msg, "exit_code": EXIT_INCONCLUSIVE})
    else:
        human(args, f"{args.algorithm}: {msg}", "result: inconclusive (timeout)")
    return EXIT_INCONCLUSIVE


def _fmt(val) -> str:
    return "n/a" if val is None else (f"{val:.6g}" if isinstance(val, float) else str(val))


def plot_run(trace, lattice, roles, path, phi) -> str:
    """Draw trajectories (thin), the final formation (roles coloured), headings and the
    spanning tree read from the final controller states' ``"parent"``; a goal-set target's
    cells as open squares."""
    import numpy as np

    from swarmproof.checkers.plotting import ROLE_COLORS, new_figure, save_png
    from swarmproof.invariants.result import state_value

    fig, ax = new_figure()
    present = trace.present_at(-1)
    ids = trace.ids.tolist()
    slot = {rid: k for k, rid in enumerate(ids)}
    for k in range(trace.n):
        ax.plot(trace.poses[:, k, 0], trace.poses[:, k, 1], lw=0.6, color="0.75", zorder=1)
    final = trace.poses[-1]
    for k, s in enumerate(trace.states[-1]):
        par = state_value(s, "parent")
        if par is not None and par in slot and present[k]:
            q = slot[par]
            ax.plot([final[k, 0], final[q, 0]], [final[k, 1], final[q, 1]], color="0.2", lw=1.2, zorder=2)
    for k in range(trace.n):
        if not present[k]:
            continue
        role = (roles or {}).get(ids[k])
        if role is None:
            role = state_value(trace.states[-1][k], "role")
        role_names = tuple(getattr(lattice, "roles", ()))
        ci = role_names.index(role) if role in role_names else None
        color = ROLE_COLORS[ci % len(ROLE_COLORS)] if ci is not None else "#999999"
        x, y, th = final[k]
        alloc = state_value(trace.states[-1][k], "id")          # an allocated ID (003's anonymous robots)
        failed = bool(state_value(trace.states[-1][k], "failed"))
        marker = "x" if failed else ("*" if alloc == 0 else "o")
        ax.scatter([x], [y], s=140 if marker == "*" else 40, marker=marker, color="#d62828" if failed else color,
                   edgecolors=None if marker == "x" else "black", linewidths=1.5 if failed else 0.5, zorder=3)
        if (trace.meta.get("model") or {}).get("motion") != "grid":   # grid robots have no heading
            ax.arrow(x, y, 0.15 * phi * np.cos(th), 0.15 * phi * np.sin(th), width=0.005 * phi,
                     color="black", zorder=4, length_includes_head=True)
        text = str(ids[k]) if alloc is None else f"{ids[k]}:ID{alloc}" + (" leader" if alloc == 0 else "") + (
            " failed" if failed else "")
        ax.annotate(text, (x, y), xytext=(3, 3), textcoords="offset points", fontsize=7)
    goals = getattr(lattice, "positions", None)
    if callable(goals):
        g = goals()
        ax.scatter(g[:, 0], g[:, 1], s=120, marker="s", facecolors="none", edgecolors="#2a9d8f",
                   linewidths=1.0, zorder=0, label="goal cells")
    ax.set_title(f"{trace.meta.get('algorithm')} on {lattice.name}: {trace.n} robots, "
                 f"{trace.steps} steps ({trace.meta.get('status')})")
    return save_png(fig, path)
