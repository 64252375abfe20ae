"""``swarmproof prove [LEMMA ... | --algorithm REF | --list] [--json] [--rlimit N] [--timeout S]``: the z3 proof suite.

Runs :func:`swarmproof.checkers.proofs.run_suite` (docs/proofs.md).  Every
lemma is proved by asserting its negation (``unsat``), its premises are shown
satisfiable, and a negative control (one premise weakened) must be refuted
with a concrete counterexample.

Exit codes (DESIGN.md section 2): 0 every requested lemma proved, 1 a
counterexample, 2 an unknown lemma id or a non-positive timeout, 3
inconclusive (z3 ``unknown``, a spent budget, vacuous premises, or a negative
control that was not refuted).

z3's work is budgeted in its deterministic resource units (``rlimit``, per lemma), not in
seconds, so a loaded machine gives the same verdicts as an idle one; ``--timeout`` is only an
outer wall-clock cap (docs/proofs.md "Budgets").
"""

from __future__ import annotations

import argparse

NAME = "prove"
HELP = "run the z3 proof suite of the safety lemmas (bounded range, NCLB, spanning tree, ...)"
DESCRIPTION = (
    "Prove the safety lemmas of Song & O'Kane 2014/2016 with z3: bounded range (Lemma 7), "
    "NCLB link kept, spanning tree kept (Lemma 11), relocate stays in range, safe region "
    "non-empty, intermediate goal in region, and the normalisation lemmas they rely on. "
    "With no LEMMA, all of them. Exit 0 all proved, 1 a counterexample, 2 usage error, "
    "3 inconclusive."
)


def _timeout(text: str) -> float:
    from swarmproof.checkers.proofs import MAX_TIMEOUT_S

    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"--timeout={text!r} is not a number of seconds") from None
    if not 0 < x <= MAX_TIMEOUT_S:
        raise argparse.ArgumentTypeError(f"--timeout={text!r} must be > 0 and at most {MAX_TIMEOUT_S:g} "
                                         "seconds (one day)")
    return x


def _rlimit(text: str) -> int:
    from swarmproof.checkers.proofs import DEFAULT_RLIMIT, MAX_RLIMIT

    try:
        x = int(text.replace("_", ""))
    except ValueError:
        try:
            f = float(text)            # 2e8, as the docs write budgets
            x = int(f) if f.is_integer() else None
        except (ValueError, OverflowError):
            x = None
    if x is None or not 1 <= x <= MAX_RLIMIT:
        raise argparse.ArgumentTypeError(f"--rlimit={text!r} must be an integer from 1 to {MAX_RLIMIT} "
                                         f"(z3's resource units; e.g. {DEFAULT_RLIMIT}, the default)")
    return x


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("lemmas", nargs="*", metavar="LEMMA",
                        help="lemma ids to prove (default: the whole suite)")
    parser.add_argument("--algorithm", metavar="REF", default=None,
                        help="prove the lemmas this algorithm declares (its class attribute lemmas): a "
                             "registry name or module:qualname")
    parser.add_argument("--list", action="store_true",
                        help="list every lemma with its algorithms (as `swarmproof list lemmas`) and prove nothing")
    parser.add_argument("--json", action="store_true",
                        help="print one JSON document on stdout and nothing else there")
    parser.add_argument("--rlimit", type=_rlimit, default=None, metavar="N",
                        help="z3's work budget per lemma in its deterministic resource units, for "
                             "every lemma named (default: each lemma's own, else 200000000)")
    parser.add_argument("--timeout", type=_timeout, default=None, metavar="S",
                        help="outer wall-clock cap per lemma in seconds (default 300); the rlimit "
                             "budget decides, the cap only stops a machine far slower than expected")


def status_exit_code(statuses) -> int:
    """0 all proved, 1 any counterexample, else 3 (inconclusive or nothing run).

    >>> status_exit_code(["proved", "inconclusive", "counterexample"])
    1
    >>> status_exit_code(["proved", "inconclusive"]), status_exit_code(["proved"])
    (3, 0)
    """
    from swarmproof.models.verdict import Verdict

    to_verdict = {"proved": Verdict.PROVED, "counterexample": Verdict.VIOLATED,
                  "inconclusive": Verdict.INCONCLUSIVE}
    return Verdict.combine(to_verdict[s] for s in statuses).exit_code


def format_human(results) -> list:
    """The human report: a table id / status / seconds / cites, a summary line,
    then each counterexample as numbers and each inconclusive reason."""
    lines = [f"{'lemma':<36} {'status':<15} {'kind':<12} {'vacuity':<14} {'seconds':>8} {'rlimit used':>12}  cites"]
    for r in results:
        vac = (r.vacuity or {}).get("verdict", "")
        used = _used(r.rlimit)
        lines.append(f"{r.id:<36} {r.status:<15} {r.kind:<12} {vac:<14} {r.seconds:>8.3f} {used:>12}  "
                     f"{'; '.join(r.cites)}")
    counts = {k: sum(r.status == k for r in results)
              for k in ("proved", "counterexample", "inconclusive")}
    lines.append(f"{len(results)} lemmas: {counts['proved']} proved, "
                 f"{counts['counterexample']} counterexample, {counts['inconclusive']} inconclusive")
    for r in results:
        if r.status == "counterexample":
            lines.append(f"counterexample to {r.id} ({r.reason}):")
            lines.extend(f"  {k} = {v!r}" for k, v in r.counterexample.items())
        elif r.status == "inconclusive":
            lines.append(f"inconclusive {r.id}: {r.reason}")
    for r in results:
        for gap in r.not_proved:
            lines.append(f"not proved by {r.id}: {gap}")
    return lines


def _used(rlimit: dict) -> str:
    """``used/budget`` as a share: ``"12%"``; ``"spent"`` once z3 reached the budget (its count
    may run a little past it); ``""`` when nothing was recorded.

    >>> _used({"budget": 200, "used": 24}), _used({"budget": 1000, "used": 1720}), _used({})
    ('12%', 'spent', '')
    """
    if not rlimit or not rlimit.get("budget"):
        return ""
    if rlimit["used"] >= rlimit["budget"]:
        return "spent"
    return f"{100 * rlimit['used'] / rlimit['budget']:.0f}%"


def run(args) -> int:
    import sys

    from swarmproof.checkers.proofs import DEFAULT_TIMEOUT_S, run_suite
    from swarmproof.commands import StatusLine, emit_json, human
    from swarmproof.models.errors import UsageError

    if args.list:
        if args.lemmas or args.algorithm:
            raise UsageError("--list lists every lemma: it takes no LEMMA and no --algorithm",
                             fix="swarmproof prove --list, or swarmproof list lemmas")
        from swarmproof.commands import list as list_command

        return list_command.run(argparse.Namespace(kind="lemmas", json=args.json))
    ids = args.lemmas or None
    if args.algorithm is not None:
        from swarmproof.checkers.proofs import algorithm_lemmas

        if args.lemmas:
            raise UsageError(f"give lemma ids or --algorithm={args.algorithm}, not both",
                             fix=f"swarmproof prove --algorithm {args.algorithm}")
        ids = algorithm_lemmas(args.algorithm)
    timeout = DEFAULT_TIMEOUT_S if args.timeout is None else args.timeout
    progress = StatusLine(sys.stderr, "prove") if sys.stderr.isatty() else None
    try:
        results = run_suite(ids, timeout_s=timeout, rlimit=args.rlimit, progress=progress)
    finally:
        if progress is not None:
            progress.clear()
    if args.json:
        emit_json({"lemmas": [r.to_dict() for r in results], "timeout": timeout, "rlimit": args.rlimit})
    else:
        human(args, *format_human(results))
    return status_exit_code(r.status for r in results)
