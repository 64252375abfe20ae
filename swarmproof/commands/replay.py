"""``swarmproof replay``: re-run a counterexample file and judge its property again.

Exit codes: 1 while the counterexample still reproduces (the property is
violated again), 0 once it no longer does (the property held on the replayed
run), 3 when the replay cannot tell (inconclusive: e.g. the run hit its step
cap, or a pose overflowed), 2 unreadable or malformed file, or a file made with
another reading of the algorithm than it runs now (the message names the
registered reading that reproduces it, or where to get it).
"""

from __future__ import annotations

from swarmproof.checkers.replay import gif_replay, plot_replay
from swarmproof.commands import emit_json, human

NAME = "replay"
HELP = ("re-run a swarmproof-counterexample/1 file; exit 1 while it reproduces, 0 once it does not, "
        "3 when the replay is inconclusive")
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def add_arguments(p) -> None:
    p.add_argument("file", metavar="FILE", help="a swarmproof-counterexample/1 file (swarmproof explore --out)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--plot", metavar="PNG", help="draw the trajectories with the violation marked")
    p.add_argument("--gif", metavar="GIF", help="animate the replayed run (animated GIF), the violation step marked")


def run(args) -> int:
    from swarmproof.checkers.replay import replay_file

    # --plot and --gif were checked before any work (swarmproof.commands.outputs)
    rr = replay_file(args.file)
    doc = rr.as_dict()
    doc["file"] = args.file
    if args.plot is not None:
        doc["plot"] = plot_replay(rr, args.plot)
    if args.gif is not None:
        doc["gif"] = gif_replay(rr, args.gif)
    if args.json:
        emit_json(doc)
    lines = rr.counterexample.format_steps()
    lines.append(f"replay: {'REPRODUCED' if rr.reproduced else 'not reproduced'} ({rr.verdict.status}): "
                 f"{rr.verdict.message}")
    if args.plot is not None:
        lines.append(f"plot: {doc['plot']}")
    if args.gif is not None:
        lines.append(f"gif: {doc['gif']}")
    human(args, *lines)
    return replay_exit_code(rr.reproduced, rr.verdict.status)


def replay_exit_code(reproduced: bool, status: str) -> int:
    """1 while the counterexample reproduces, 3 when the replay could not judge it (inconclusive is
    never a pass), else 0.

    >>> replay_exit_code(True, "violated"), replay_exit_code(False, "inconclusive"), replay_exit_code(False, "held")
    (1, 3, 0)
    """
    from swarmproof.models.verdict import EXIT_INCONCLUSIVE, EXIT_OK, EXIT_VIOLATED

    if reproduced:
        return EXIT_VIOLATED
    return EXIT_INCONCLUSIVE if status == "inconclusive" else EXIT_OK
