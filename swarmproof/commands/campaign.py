"""``swarmproof campaign SPEC``: a matrix of explorations and experiments on Dask (docs/campaigns.md).

Runs every task of a ``swarmproof-campaign/1`` file on an embedded Dask
``LocalCluster`` (one process per core; ``--workers N``) or on an existing
cluster (``--scheduler tcp://HOST:PORT``); results stream into
``DIR/results.sqlite`` and ``DIR/counterexamples/`` (``--out DIR``, default
``campaign-NAME``), and ``DIR/report.md`` sums them up.  ``--resume`` runs
only the unfinished tasks of a campaign that was cut short.

Exit codes: 0 every task held (or, for a paper experiment's trials, was
measured: figures, no claim judged); 1 a task found a violation (with a
counterexample); 2 a bad spec, an unreachable scheduler, an unusable --out
folder or a full disk (with the cause and the fix; what finished is kept);
3 inconclusive or cut short; 130 stopped by Ctrl-C (no report.md is written; what
finished is kept in results.sqlite and --resume continues it).
"""

from __future__ import annotations

import sys

from swarmproof.commands import StatusLine, emit_json, human

NAME = "campaign"
HELP = "run a campaign file (explorations and experiments) on Dask, resumable"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def add_arguments(p) -> None:
    p.add_argument("spec", metavar="SPEC", help="a swarmproof-campaign/1 file (YAML or JSON; campaigns/ has examples)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="an existing Dask scheduler, e.g. tcp://127.0.0.1:8786 (default: an embedded local cluster)")
    p.add_argument("--workers", type=int, metavar="N",
                   help="processes of the embedded cluster (default: one per core)")
    p.add_argument("--out", metavar="DIR", help="results folder (default: campaign-NAME)")
    p.add_argument("--resume", action="store_true", help="run only the tasks DIR does not hold yet")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout (no wall-clock figures)")


class _Bar(StatusLine):
    """The campaign's progress bar: a :class:`~swarmproof.commands.StatusLine` fed task counts."""

    def __call__(self, done: int, total: int, violated: int) -> None:
        frac = done / total if total else 1.0
        super().__call__(f"[{'#' * int(24 * frac):<24}] {done}/{total} tasks, {violated} violated")


def run(args) -> int:
    import os

    from swarmproof.checkers.campaign import run_campaign
    from swarmproof.checkers.campaign_report import format_summary, write_report
    from swarmproof.models.campaign_spec import load_campaign_file

    from swarmproof.checkers.explore import _safe

    spec = load_campaign_file(args.spec)
    out = args.out or f"campaign-{_safe(spec.name)}"     # run_campaign checks --workers first
    bar = _Bar(sys.stderr, "campaign") if sys.stderr.isatty() else None
    try:
        result = run_campaign(spec, out_dir=out, scheduler=args.scheduler, workers=args.workers,
                              resume=args.resume, progress=bar)
    finally:
        if bar is not None:
            bar.clear()
    from swarmproof.models.interrupt import interrupted

    if interrupted():    # Ctrl-C: exit 130 without a report.md (it could look complete); what finished is kept
        sys.stderr.write(f"swarmproof campaign: {len(result.results)}/{len(result.tasks)} tasks finished, kept in "
                         f"{os.path.join(out, 'results.sqlite')}; --resume continues the campaign\n")
        raise KeyboardInterrupt
    report = write_report(result)
    if args.json:
        emit_json(result.to_json())
    human(args, *format_summary(result), f"report: {report}; results: {os.path.join(out, 'results.sqlite')}")
    return result.exit_code
