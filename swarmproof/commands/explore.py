"""``swarmproof explore``: hunt counterexamples to properties of an algorithm with Hypothesis.

Draws connected starts on the bundled periodic lattices, runs ALGORITHM and
judges each requested property (default: every registered one -- connectivity,
tree_links, termination, formation, collision, deadlock, oscillation, premises,
and any a user registered; ``--property module:name`` imports a user's own,
swarmproof.invariants.registry); a violation is
shrunk and, with ``--out DIR``, written as a swarmproof-counterexample/1 file
to re-run with ``swarmproof replay FILE``.  "held" means held over what was
explored, never proved.

Exit codes: 0 every property held over the scenarios explored; 1 a property
was violated; 2 usage error; 3 a property is inconclusive (budget spent, runs capped).
"""

from __future__ import annotations

import math
import re
import sys

from swarmproof.commands import add_tree_link_mode, emit_json, human
from swarmproof.models.errors import UsageError

NAME = "explore"
HELP = "hunt counterexamples to an algorithm's properties (Hypothesis)"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def add_arguments(p) -> None:
    p.add_argument("algorithm", metavar="ALGORITHM",
                   help="registry name, e.g. song2016, song2014, or module:qualname of your algorithm class")
    p.add_argument("--property", action="append", dest="properties", metavar="P",
                   help="property to check: a registered name, or module:name of your own "
                        "(a Property, or a check registered with @property_check); repeatable (default: all)")
    p.add_argument("--target", "--lattice", action="append", dest="targets", metavar="[KIND:]NAME|FILE",
                   help="draw scenarios on this target, repeatable: a bundled lattice name or a lattice-graph/1 "
                        "file of your own (default: the bundled periodic lattices)")
    p.add_argument("--strict", action="store_true",
                   help="refuse a lattice file of yours that check-lattice does not pass at its range "
                        "(default: explore it with a warning)")
    p.add_argument("--budget", type=_budget, default=60.0, metavar="SECONDS|none",
                   help="wall-clock budget for the whole exploration (default 60); 'none': no time limit, "
                        "--max-examples alone bounds the search (the same verdicts on any machine, for CI gates)")
    p.add_argument("--max-examples", type=int, default=100, metavar="N",
                   help="Hypothesis examples per property (default 100)")
    p.add_argument("--robots", default=None, metavar="MIN..MAX",
                   help="number of robots (default 3..8; with --exhaustive 3, and MIN..MAX searches each team "
                        "size in turn up to the first violation)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="Hypothesis seed (default 0)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--out", metavar="DIR", help="write counterexample files into DIR")
    p.add_argument("--fault", action="append", dest="faults", default=[], metavar="KIND",
                   help="draw faults of this kind per scenario, repeatable: schedule, crashes, drops, additions, noise, "
                        "delays "
                        "(each breaks the robot-model assumptions it breaks; reported)")
    p.add_argument("--v", type=float, metavar="V", help="maximum linear speed (default: the algorithm's)")
    p.add_argument("--speeds", metavar="V1,V2,...",
                   help="every scenario draws its speed v from these (shrinking goes toward the first); "
                        "not with --v")
    p.add_argument("--omega", type=float, metavar="W", help="maximum angular speed, rad per time")
    p.add_argument("--dt", type=float, metavar="DT", help="step length")
    p.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="algorithm parameter (Params.extra), repeatable")
    p.add_argument("--allow-violations", action="store_true",
                   help="explore even when the parameters break a paper assumption (reported)")
    p.add_argument("--max-steps", type=int, metavar="K", help="step cap per run (default: the algorithm's)")
    add_tree_link_mode(p)
    p.add_argument("--invariant", action="append", dest="invariants", metavar="NAME",
                   help="the invariants property checks only this one of the algorithm's invariants "
                        "(repeatable; default: all), e.g. wang2020's j2_monotone")
    # argparse takes "-1,0.05" for an option ("--speeds: expected one argument"); a value that reads as
    # numbers (a negative one, a list of them) is a value here, so `--speeds -1,0.05` gets the explorer's
    # message about -1 (argparse's own matcher knows only a lone "-1" or "-.5")
    p._negative_number_matcher = _NUMBERS
    p.add_argument("--database", metavar="DIR",
                   help="keep Hypothesis's example database in DIR so a rerun finds known failures at once")
    g = p.add_argument_group("exhaustive bounded checking (--exhaustive; docs/exhaustive.md)")
    g.add_argument("--exhaustive", action="store_true",
                   help="try every choice sequence within a bound (steps, deviations, choice kinds) from each "
                        "start instead of sampling: held means held for every one of them")
    g.add_argument("--initial", metavar="FILE", help="the one start to search from (an initial-configuration file)")
    g.add_argument("--starts", type=int, default=None, metavar="N",
                   help="N seeded starts (the ones simulate --robots N --seed S draws), seeds S, S+1, ...")
    g.add_argument("--deviations", type=int, default=None, metavar="K",
                   help="most non-default choices per sequence (default 2); deepened from 0, so a "
                        "counterexample has the fewest")
    g.add_argument("--choices", default=None, metavar="KIND,...",
                   help="choice kinds to enumerate: activate, loss, delay, duplicate, reorder, crash "
                        "(default activate)")
    g.add_argument("--max-delay", type=int, default=None, metavar="D", help="largest delay of a delay choice (default 1)")
    g.add_argument("--max-crashes", type=int, default=None, metavar="C",
                   help="most robots a crash choice crashes in one run (default 1)")
    g.add_argument("--draw-starts", type=int, metavar="N",
                   help="Hypothesis draws N connected starts of --robots MIN..MAX robots (seeded by --seed), each "
                        "searched exhaustively; a violating start is shrunk to the smallest it finds (the default "
                        "without --initial or --starts: 5)")
    g.add_argument("--max-runs", type=int, metavar="N",
                   help="runs per start and property before the search gives up: inconclusive with the coverage")
    g.add_argument("--no-symmetry", action="store_true",
                   help="no symmetry reduction for anonymous robots (to measure it)")


def _options(args) -> dict | None:
    """The property options the flags give (None: none)."""
    opts = {}
    if args.tree_link_mode:
        opts["tree_link_mode"] = args.tree_link_mode
    if args.invariants:
        opts["invariants"] = tuple(args.invariants)
    return opts or None


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
#: A command-line word that is a negative number or a comma-separated list of numbers starting with one.
_NUMBERS = re.compile(rf"^-(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?:,{_NUMBER})*$")


def _budget(text: str):
    """``--budget``: seconds, or ``none`` for no wall-clock limit (argparse names the option and
    what is expected when this raises: ``argument --budget: ...``).

    >>> _budget("60"), _budget("none")
    (60.0, None)
    >>> _budget("soon")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: 'soon' is not a number of seconds nor 'none' (e.g. --budget 60)
    """
    import argparse

    if text.strip().lower() == "none":
        return None
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds nor 'none' "
                                         "(e.g. --budget 60)") from None


def parse_robots(text: str) -> tuple[int, int]:
    """``"3..8"`` -> ``(3, 8)``; ``"5"`` -> ``(5, 5)``.

    >>> parse_robots("3..8"), parse_robots("5")
    ((3, 8), (5, 5))
    """
    m = re.fullmatch(r"\s*(\d+)\s*(?:\.\.\s*(\d+)\s*)?", text or "")
    if not m:
        raise UsageError(f"--robots {text!r} must be MIN..MAX or N", fix="e.g. --robots 3..8")
    lo = int(m.group(1))
    hi = int(m.group(2)) if m.group(2) is not None else lo
    if not 1 <= lo <= hi:
        raise UsageError(f"--robots {text!r} must satisfy 1 <= MIN <= MAX", fix="e.g. --robots 3..8")
    return lo, hi


def parse_speeds(text: str | None) -> list[float] | None:
    """``"0.05,0.4,0.8"`` -> ``[0.05, 0.4, 0.8]``; None stays None.

    >>> parse_speeds("0.05, 0.4,0.8")
    [0.05, 0.4, 0.8]
    """
    if text is None:
        return None
    out = []
    for part in text.split(","):
        try:
            out.append(float(part))
        except ValueError:
            raise UsageError(f"--speeds {text!r}: {part.strip()!r} is not a number",
                             fix="e.g. --speeds 0.05,0.4,0.8") from None
    return out


def _progress():
    if not sys.stderr.isatty():
        return None

    def show(prop: str, k: int, total: int) -> None:
        sys.stderr.write(f"\rexplore {prop}: example {k} (max {total} + shrinking)   ")
        sys.stderr.flush()

    return show


#: Flags of the sampling explorer that an exhaustive search has no use for, and its own flags.
_SAMPLING_ONLY = (("faults", "--fault", []), ("speeds", "--speeds", None), ("database", "--database", None))
_EXHAUSTIVE_ONLY = (("initial", "--initial", None), ("starts", "--starts", None), ("deviations", "--deviations", None),
                    ("choices", "--choices", None), ("max_delay", "--max-delay", None),
                    ("max_crashes", "--max-crashes", None), ("max_runs", "--max-runs", None),
                    ("draw_starts", "--draw-starts", None),
                    ("no_symmetry", "--no-symmetry", False))


def run(args) -> int:
    if args.exhaustive:
        return _run_exhaustive(args)
    for attr, flag, default in _EXHAUSTIVE_ONLY:
        if getattr(args, attr) != default:
            raise UsageError(f"{flag} is for exhaustive checking only", fix=f"add --exhaustive, or drop {flag}")
    from swarmproof.checkers.explore import explore

    robots = parse_robots(args.robots or "3..8")
    if args.budget is not None and not (math.isfinite(args.budget) and args.budget > 0):
        raise UsageError(f"--budget {args.budget!r} must be a number of seconds > 0, or none",
                         fix="e.g. --budget 60, or --budget none to bound the search by --max-examples alone")
    from swarmproof.checkers.watchdog import MAX_LIMIT_S
    if args.budget is not None and args.budget > MAX_LIMIT_S:
        raise UsageError(f"--budget {args.budget:g} is more than {MAX_LIMIT_S:g} seconds (about 115 days)",
                         fix="give fewer seconds, or --budget none to bound the search by --max-examples alone")
    if args.max_examples < 1:
        raise UsageError(f"--max-examples {args.max_examples!r} must be >= 1", fix="e.g. --max-examples 100")
    from swarmproof.commands.simulate import _parse_extra

    from swarmproof.reference_impl.engine.parameters import check_motion_value

    params = {k: getattr(args, k) for k in ("v", "omega", "dt") if getattr(args, k) is not None}
    for name, val in params.items():
        check_motion_value(name, val)          # > 0, with the reason (issue 29)
    if args.param:
        params["extra"] = _parse_extra(args.param)
    if args.max_steps is not None and args.max_steps < 1:
        raise UsageError(f"--max-steps {args.max_steps!r} must be >= 1", fix="e.g. --max-steps 500")
    if args.out is not None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(args.out, "--out")     # before the search, not after it
    progress = _progress()
    report = explore(args.algorithm, args.properties, budget=args.budget, max_examples=args.max_examples,
                     robots=robots, seed=args.seed, out_dir=args.out, progress=progress,
                     database_dir=args.database, draw_faults=tuple(args.faults), params=params,
                     allow_violations=args.allow_violations, max_steps=args.max_steps,
                     speeds=parse_speeds(args.speeds), lattices=args.targets, strict=args.strict,
                     options=_options(args))
    if progress is not None:
        sys.stderr.write("\n")
    doc = report.as_dict()
    for w in report.warnings:
        sys.stderr.write(f"swarmproof explore: warning: {w}\n")
    if args.json:
        emit_json(doc)
    lines = [f"explore {report.algorithm}: seed {report.seed}, robots {robots[0]}..{robots[1]}, "
             f"max {report.max_examples} examples per property" +
             (f", v drawn from {list(report.speeds)}" if report.speeds else ""),
             f"  assumptions kept: {', '.join(report.kept_assumptions) or '-'}; "
             f"broken: {', '.join(report.broken_assumptions) or '-'}"]
    for name, v in report.properties.items():
        if v.status == "not_applicable":         # no verdict: nothing was run for it
            lines.append(f"  {name:<13} {'n/a':<12} {v.message}")
            continue
        lines.append(f"  {name:<13} {v.status:<12} {v.scenarios} scenarios, {v.steps} steps: {v.message}")
        if v.counterexample is not None:
            lines += ["    " + s for s in v.counterexample.format_steps()]
            if v.counterexample_path:
                lines.append(f"    replay: swarmproof replay {v.counterexample_path}")
            else:
                lines.append("    (pass --out DIR to write the counterexample file)")
    human(args, *lines)
    return report.exit_code


def _exhaustive_progress():
    if not sys.stderr.isatty():
        return None
    import time

    last = [0.0]

    def show(prop: str, d: dict) -> None:
        now = time.monotonic()
        if now - last[0] < 0.5:
            return
        last[0] = now
        sys.stderr.write(f"\rexhaustive {prop}: K={d['deviations']} runs {d['runs']}, states {d['states']}, "
                         f"depth {d['depth']}   ")
        sys.stderr.flush()

    return show


#: Starts Hypothesis draws for ``--exhaustive`` when none are given (``--initial``, ``--starts``).
DEFAULT_DRAWN_STARTS = 5


def _run_exhaustive(args) -> int:
    """``explore --exhaustive``: every choice sequence within the bound (checkers/exhaustive.py)."""
    from swarmproof.checkers.exhaustive import Bound, exhaustive
    from swarmproof.commands.simulate import _parse_extra

    for attr, flag, default in _SAMPLING_ONLY:
        if getattr(args, attr) != default:
            raise UsageError(f"{flag} is for sampling exploration; --exhaustive enumerates the choices it names",
                             fix=f"drop {flag} (use --choices for the decisions to enumerate)")
    if args.max_examples != 100:
        raise UsageError("--max-examples is for sampling exploration", fix="drop it; bound the search with "
                         "--max-steps, --deviations and --choices (and --max-runs / --budget)")
    steps = 20 if args.max_steps is None else args.max_steps
    kinds = tuple(k.strip() for k in ("activate" if args.choices is None else args.choices).split(",") if k.strip())
    if not kinds:
        raise UsageError(f"--choices {args.choices!r} names no choice kind", fix="e.g. --choices activate,loss")
    bound = Bound(steps=steps, deviations=2 if args.deviations is None else args.deviations, kinds=kinds,
                  max_delay=1 if args.max_delay is None else args.max_delay,
                  max_crashes=1 if args.max_crashes is None else args.max_crashes)
    initial = None
    if args.initial is not None:
        from swarmproof.reference_impl import initial as initial_mod

        initial = initial_mod.from_file(args.initial)
    lo, hi = parse_robots(args.robots or "3")
    if initial is not None and args.robots is not None and (lo, hi) != (initial.n, initial.n):
        raise UsageError(f"--robots {args.robots} disagrees with --initial {args.initial!r} ({initial.n} robots)",
                         fix="drop --robots or make them agree")
    if args.budget is not None and not (math.isfinite(args.budget) and args.budget > 0):
        raise UsageError(f"--budget {args.budget!r} must be a number of seconds > 0, or none",
                         fix="e.g. --budget 60, or --budget none to bound the search by its bound alone")
    if args.targets and len(args.targets) > 1:
        raise UsageError(f"--target given {len(args.targets)} times: an exhaustive search runs on one target",
                         fix="give one --target")
    params = {k: getattr(args, k) for k in ("v", "omega", "dt") if getattr(args, k) is not None}
    if args.param:
        params["extra"] = _parse_extra(args.param)
    if args.out is not None:
        from swarmproof.models.fileio import check_output_dir

        check_output_dir(args.out, "--out")
    if initial is None:                 # the largest team first: a bound it cannot take, before any search
        from swarmproof.checkers.algorithm_spec import resolve_algorithm

        bound.check_applies(resolve_algorithm(args.algorithm).build(n_robots=hi), hi)
    progress = _exhaustive_progress()
    reports = []
    if initial is not None and args.starts is not None:
        raise UsageError("--starts N gives seeded starts: not with --initial FILE (one start of yours)",
                         fix="drop --starts, or drop --initial")
    if args.draw_starts is None and initial is None and args.starts is None:
        args.draw_starts = DEFAULT_DRAWN_STARTS      # Hypothesis-drawn starts unless starts are given
    if args.draw_starts is not None:
        if initial is not None or args.starts is not None:
            raise UsageError("--draw-starts draws the starts: not with --initial or --starts",
                             fix="drop --initial / --starts, or --draw-starts")
        if args.draw_starts < 1:
            raise UsageError(f"--draw-starts {args.draw_starts!r} must be >= 1", fix="e.g. --draw-starts 20")
    for n in (range(lo, hi + 1) if args.draw_starts is None else (lo,)):
        report = exhaustive(args.algorithm, args.properties, target=(args.targets or [None])[0], robots=n,
                            seed=args.seed, initial=initial, starts=1 if args.starts is None else args.starts,
                            bound=bound, params=params,
                            options=_options(args), max_runs=args.max_runs, budget=args.budget,
                            symmetry=not args.no_symmetry, out_dir=args.out, progress=progress,
                            draw_starts=args.draw_starts, draw_robots=(lo, hi) if args.draw_starts else None)
        reports.append(report)
        if report.exit_code == 1 or initial is not None:
            break           # the smallest team with a violation (teams in increasing size)
    if progress is not None:
        sys.stderr.write("\n")
    if args.json:
        emit_json(reports[0].as_dict() if len(reports) == 1 else
                  {"mode": "exhaustive", "teams": [r.as_dict() for r in reports],
                   "exit_code": max(r.exit_code for r in reports)})
    lines = []
    for report in reports:
        team = f"{lo}..{hi}" if args.draw_starts and hi > lo else report.robots
        lines.append(f"explore {report.algorithm} --exhaustive: {team} robots, starts "
                     f"{', '.join(report.starts)}, bound {report.bound.text()}"
                     + (", symmetry reduction (anonymous robots)" if report.symmetric else ""))
        if report.broken_assumptions:
            lines.append(f"  the choices break: {', '.join(report.broken_assumptions)}")
        for name, v in report.properties.items():
            if v.status == "not_applicable":
                lines.append(f"  {name:<13} {'n/a':<12} {v.message}")
                continue
            stats = (f"{v.runs} runs, {v.distinct_states} states, {v.pruned} pruned"
                     + (f", {v.symmetric_pruned} by symmetry" if report.symmetric else ""))
            lines.append(f"  {name:<13} {v.status:<12} {stats}: {v.message}")
            if v.counterexample is not None:
                lines += ["    " + s for s in v.counterexample.format_steps()]
                lines.append(f"    replay: swarmproof replay {v.counterexample_path}" if v.counterexample_path
                             else "    (pass --out DIR to write the counterexample file)")
    human(args, *lines)
    return max(r.exit_code for r in reports)
