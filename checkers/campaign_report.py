"""The campaign report: ``DIR/report.md`` and a PNG per experiment cell (``DIR/plots/``).

The verdict matrix (one line per cell: verdict, held / violated /
inconclusive counts, the fewest scenarios before a first failure, the
smallest counterexample), then, for each experiment cell, its metrics by team
size (mean over seeds: execution steps, total distance) and a plot of them.
Deterministic: no wall-clock figure (the timings stay in the store's
``timings`` table).
"""

from __future__ import annotations

import os

__all__ = ["format_summary", "markdown", "write_report", "plot_experiment"]


def _counts(c: dict) -> str:
    n = c["counts"]
    return f"{n['held']} held, {n['violated']} violated, {n['inconclusive']} inconclusive"


def format_summary(result) -> list[str]:
    """The human lines: one per cell, then the campaign's verdict line."""
    from swarmproof.models.citations import readable

    lines = []
    cells = result.cells()
    w = max([len(c["cell"]) for c in cells] + [4])
    for c in cells:
        extra = ""
        small = c["smallest_counterexample"]
        if small:
            extra = f"; smallest counterexample: {small['robots']} robots, {os.path.join(result.out_dir, small['path'])}"
        unfinished = c["tasks"] - c["finished"]
        if unfinished:
            extra += f"; {unfinished} task(s) not finished"
        lines.append(readable(f"{c['cell']:<{w}}  {c['verdict']:<12}  {_counts(c)}{extra}"))
    word = {0: "HELD", 1: "VIOLATED", 3: "INCONCLUSIVE"}.get(result.exit_code, "?")
    cut = " (cut short: --resume continues it)" if result.cut_short else ""
    lines.append(f"campaign {result.spec.name}: {word}: {len(result.results)}/{len(result.tasks)} tasks finished, "
                 f"{result.ran} run now{cut}")
    return lines


def _experiment_rows(result, cell_label: str) -> dict:
    """``{(target, n): [figures, ...]}`` of one experiment cell's finished tasks."""
    out: dict = {}
    for t in result.tasks:
        if t.cell != cell_label or t.key not in result.results:
            continue
        out.setdefault((t.args["target"], t.args["robots"]), []).append(result.results[t.key]["figures"])
    return out


def _mean(xs):
    xs = [float(x) for x in xs if isinstance(x, (int, float))]
    return None if not xs else sum(xs) / len(xs)


def plot_experiment(result, cell_label: str, path: str) -> str | None:
    """Execution steps and total distance by team size, one line per target; None when empty."""
    from swarmproof.checkers.plotting import new_figure, save_png

    rows = _experiment_rows(result, cell_label)
    if not rows:
        return None
    fig, ax = new_figure(7.0, 4.0)
    ax.set_aspect("auto")
    for target in sorted({t for t, _ in rows}):
        ns = sorted(n for t, n in rows if t == target)
        ys = [_mean(f.get("execution_steps") for f in rows[(target, n)]) for n in ns]
        ax.plot(ns, [y if y is not None else float("nan") for y in ys], "o-", label=target)
    ax.set_xlabel("robots")
    ax.set_ylabel("execution steps (mean over seeds)")
    ax.set_title(cell_label, fontsize=10)
    ax.legend(fontsize=8)
    return save_png(fig, path)


def markdown(result, plots: dict | None = None) -> str:
    from swarmproof.models.citations import readable

    plots = plots or {}
    lines = [f"# Campaign {result.spec.name}", "",
             f"{len(result.results)} of {len(result.tasks)} tasks finished; exit code {result.exit_code}"
             + (" (cut short: `--resume` continues it)" if result.cut_short else "") + ".", "",
             "| cell | verdict | held | violated | inconclusive | scenarios before the first failure | "
             "smallest counterexample |", "|---|---|---:|---:|---:|---:|---|"]
    for c in result.cells():
        n = c["counts"]
        small = c["smallest_counterexample"]
        cx = f"{small['robots']} robots: `{small['path']}`" if small else ""
        ffs = "" if c["first_failure_scenarios"] is None else str(c["first_failure_scenarios"])
        lines.append(f"| {c['cell']} | {c['verdict']} | {n['held']} | {n['violated']} | {n['inconclusive']} | "
                     f"{ffs} | {cx} |")
    for c in result.cells():
        if c["kind"] != "simulate":
            continue
        rows = _experiment_rows(result, c["cell"])
        lines += ["", f"## {c['cell']}", "", "| target | robots | runs | execution steps (mean) | "
                  "total distance (mean) | satisfied |", "|---|---:|---:|---:|---:|---:|"]
        for (target, n) in sorted(rows):
            fs = rows[(target, n)]
            steps, dist = _mean(f.get("execution_steps") for f in fs), _mean(f.get("total_distance") for f in fs)
            sat = sum(f.get("satisfied") is True for f in fs)
            lines.append(f"| {target} | {n} | {len(fs)} | {'' if steps is None else f'{steps:.1f}'} | "
                         f"{'' if dist is None else f'{dist:.2f}'} | {sat}/{len(fs)} |")
        if c["cell"] in plots:
            lines += ["", f"![{c['cell']}]({plots[c['cell']]})"]
    return readable("\n".join(lines) + "\n")


def write_report(result) -> str:
    """Write ``report.md`` (and the plots) into the campaign's folder, atomically; return its path."""
    from swarmproof.models.fileio import atomic_write_text

    plots = {}
    for c in result.cells():
        if c["kind"] == "simulate":
            rel = os.path.join("plots", f"simulate-{len(plots)}.png")
            os.makedirs(os.path.join(result.out_dir, "plots"), exist_ok=True)
            if plot_experiment(result, c["cell"], os.path.join(result.out_dir, rel)):
                plots[c["cell"]] = rel
    return atomic_write_text(os.path.join(result.out_dir, "report.md"), markdown(result, plots))
