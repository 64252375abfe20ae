"""The campaign report: ``DIR/report.md`` and a PNG per experiment cell (``DIR/plots/``).

The verdict matrix (one line per cell: verdict, held / violated /
inconclusive counts, the fewest scenarios before a first failure, the
smallest counterexample), then, for each experiment cell, its figures by
target and team size (mean ± sample standard deviation over seeds: execution
steps, total distance, fulfillment ratio; runs that ended, satisfied
the target, violated a claimed property) and a plot of execution steps and
fulfillment ratio against team size; for each paper-experiment cell, the
table its experiment declares by team size (medians, ranges, counts over the
trials) and a plot of its declared figures against team size.
Deterministic: no wall-clock figure (the timings stay in the store's
``timings`` table).
"""

from __future__ import annotations

import os

__all__ = ["format_summary", "markdown", "write_report", "plot_experiment", "plot_paper_experiment", "mean_sd",
           "paper_experiment_table"]


def _counts(c: dict) -> str:
    n = c["counts"]
    na = n.get("n/a", 0)
    measured = n.get("measured", 0)
    return (f"{n['held']} held, {n['violated']} violated, {n['inconclusive']} inconclusive"
            + (f", {na} n/a (not applicable)" if na else "")
            + (f", {measured} measured (experiment trials: no claim judged)" if measured else ""))


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
    if result.exit_code == 0 and not any(c["counts"]["held"] for c in cells):
        word = "MEASURED"          # experiment trials only: every one ran, nothing was judged
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


def _numbers(xs) -> list[float]:
    return [float(x) for x in xs if isinstance(x, (int, float)) and not isinstance(x, bool)]


def _mean(xs):
    xs = _numbers(xs)
    return None if not xs else sum(xs) / len(xs)


def mean_sd(xs) -> str:
    """``mean ± sd`` (sample standard deviation, as benchmarks/bench_song2014.py) of the numbers in
    ``xs``; the mean alone for one number; empty for none.

    >>> mean_sd([1, 2, 3, None])
    '2 ± 1'
    >>> mean_sd([0.5]), mean_sd([None]), mean_sd([0.6, 0.6000000000000001])
    ('0.5', '', '0.6 ± 0')
    """
    import statistics

    xs = _numbers(xs)
    if not xs:
        return ""
    if len(xs) == 1:
        return f"{xs[0]:.3g}"
    mean, sd = statistics.mean(xs), statistics.stdev(xs)
    if sd <= 1e-12 * max(1.0, abs(mean)):      # equal up to rounding: 0.6 ± 5.6e-17 reads as noise
        sd = 0.0
    return f"{mean:.3g} ± {sd:.2g}"


#: The per-team-size figures of an experiment cell: (column, figures key, plot label); a
#: "metrics.K" key reads a target's own figure.  A column shows when some run has the figure.
EXPERIMENT_FIGURES = (("execution steps", "execution_steps", "execution steps"),
                      ("total distance", "total_distance", "total distance"),
                      ("fulfillment ratio Q", "fulfillment_ratio", "fulfillment ratio Q"),
                      ("formation quality epsilon", "metrics.epsilon", "formation quality epsilon"))


def _fig(f: dict, key: str):
    if key.startswith("metrics."):
        return (f.get("metrics") or {}).get(key.split(".", 1)[1])
    return f.get(key)


def _columns(rows: dict) -> list:
    """The EXPERIMENT_FIGURES some run of the cell has."""
    runs = [f for fs in rows.values() for f in fs]
    return [c for c in EXPERIMENT_FIGURES if any(isinstance(_fig(f, c[1]), (int, float)) for f in runs)]


def plot_experiment(result, cell_label: str, path: str) -> str | None:
    """Execution steps and the target's quality figure (fulfillment ratio Q, formation quality
    epsilon) by team size (mean ± sd over seeds), one line per target; None when the cell has
    no finished run."""
    import statistics

    from swarmproof.checkers.plotting import new_figure, save_png

    rows = _experiment_rows(result, cell_label)
    if not rows:
        return None
    cols = [c for c in _columns(rows) if c[1] != "total_distance"][:2] or [EXPERIMENT_FIGURES[0]]
    fig, _ = new_figure(5.5 * len(cols), 4.0)
    fig.clf()
    axes = fig.subplots(1, len(cols), squeeze=False)[0]
    for a, (_, key, label) in zip(axes, cols):
        a.set_aspect("auto")
        for target in sorted({t for t, _ in rows}):
            ns = sorted(n for t, n in rows if t == target)
            ys, es = [], []
            for n in ns:
                xs = _numbers(_fig(f, key) for f in rows[(target, n)])
                ys.append(statistics.mean(xs) if xs else float("nan"))
                es.append(statistics.stdev(xs) if len(xs) > 1 else 0.0)
            a.errorbar(ns, ys, yerr=es, fmt="o-", capsize=3, label=target)
        a.set_xlabel("robots")
        a.set_ylabel(f"{label} (mean ± sd over seeds)")
        a.legend(fontsize=8)
    fig.suptitle(cell_label, fontsize=10)
    return save_png(fig, path)


def _claimed_violations(fs: list[dict]) -> str:
    """Per claimed property violated in some runs, how many: ``"tree_links 50"``; ``"0"`` for none."""
    counts: dict[str, int] = {}
    for f in fs:
        for name, p in (f.get("properties") or {}).items():
            if p.get("claim") and p.get("verdict") == "violated":
                counts[name] = counts.get(name, 0) + 1
    return ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) or "0"


def markdown(result, plots: dict | None = None) -> str:
    from swarmproof.models.citations import readable

    plots = plots or {}
    lines = [f"# Campaign {result.spec.name}", "",
             f"{len(result.results)} of {len(result.tasks)} tasks finished; exit code {result.exit_code}"
             + (" (cut short: `--resume` continues it)" if result.cut_short else "") + ".", "",
             "| cell | verdict | finished | held | violated | inconclusive | n/a | measured | "
             "scenarios before the first failure | smallest counterexample |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for c in result.cells():
        n = c["counts"]
        small = c["smallest_counterexample"]
        cx = f"{small['robots']} robots: `{small['path']}`" if small else ""
        ffs = "" if c["first_failure_scenarios"] is None else str(c["first_failure_scenarios"])
        lines.append(f"| {c['cell']} | {c['verdict']} | {c['finished']}/{c['tasks']} | {n['held']} | {n['violated']} | {n['inconclusive']} | {n.get('n/a', 0)} | "
                     f"{n.get('measured', 0)} | {ffs} | {cx} |")
    for c in result.cells():
        if c["kind"] != "simulate":
            continue
        rows = _experiment_rows(result, c["cell"])
        if not rows:
            lines += ["", f"## {c['cell']}", "", "No run of this cell has finished yet."]
            continue
        cols = _columns(rows)
        head = " | ".join(f"{col} (mean ± sd)" for col, _, _ in cols)
        lines += ["", f"## {c['cell']}", "",
                  "Over the seeds of each row: the figures' mean ± sample standard deviation; *ended* "
                  "counts runs that ended (a static state, or the algorithm's own end) before the step cap; "
                  "*satisfied* counts final configurations that satisfy the target; *claims violated* "
                  "names each property the algorithm claims that some runs violated, with how many runs.", "",
                  f"| target | robots | runs | ended | {head} | satisfied | claims violated |",
                  "|---|---:|---:|---:|" + "---:|" * len(cols) + "---:|---:|"]
        for (target, n) in sorted(rows):
            fs = rows[(target, n)]
            figs = " | ".join(mean_sd(_fig(f, key) for f in fs) for _, key, _ in cols)
            ended = sum(f.get("status") in ("static", "finished") for f in fs)
            sat = sum(f.get("satisfied") is True for f in fs)
            lines.append(f"| {target} | {n} | {len(fs)} | {ended}/{len(fs)} | {figs} | {sat}/{len(fs)} | "
                         f"{_claimed_violations(fs)} |")
        if c["cell"] in plots:
            lines += ["", f"![{c['cell']}]({plots[c['cell']]})"]
    for c in result.cells():
        if c["kind"] == "experiment":
            lines += ["", f"## {c['cell']}", ""] + paper_experiment_table(result, c["cell"])
            if c["cell"] in plots:
                lines += ["", f"![{c['cell']}]({plots[c['cell']]})"]
    for c in result.cells():
        if c["kind"] == "exhaustive":
            lines += ["", f"## {c['cell']}", ""] + exhaustive_table(result, c["cell"])
    return readable("\n".join(lines) + "\n")


def exhaustive_table(result, cell_label: str) -> list[str]:
    """One row per finished task of an exhaustive cell: property, team, start, verdict, and what the
    search covered (runs, distinct states, pruned, complete) or the counterexample's deviations."""
    out = ["Every choice sequence within the cell's bound from each start (docs/exhaustive.md); *complete*: "
           "the whole bound was searched.", "",
           "| property | robots | start | verdict | runs | states | pruned | complete | deviations |",
           "|---|---:|---:|---|---:|---:|---:|---|---:|"]
    for t in result.tasks:
        if t.cell != cell_label or t.key not in result.results:
            continue
        r = result.results[t.key]
        f = r.get("figures") or {}
        dev = "" if f.get("deviations") is None else str(f["deviations"])
        out.append(f"| {t.args['property']} | {t.args['robots']} | seed {t.args['seed']} | {r['verdict']} | "
                   f"{f.get('runs', '')} | {f.get('distinct_states', '')} | {f.get('pruned', '')} | "
                   f"{'yes' if f.get('complete') else 'no'} | {dev} |")
    return out


# -- paper-experiment cells ----------------------------------------------------------------------

def _trials(result, cell_label: str, failed: dict | None = None) -> tuple:
    """``({n: [figures of the measured trials]}, declaration)`` of one experiment cell; ``failed``
    (if given) gets ``{task key: (n, error)}`` of its finished tasks that were not measured (a
    trial that raised: inconclusive)."""
    from swarmproof.checkers.campaign import MEASURED, resolve_experiment

    by_n: dict = {}
    decl = None
    for t in result.tasks:
        if t.cell != cell_label:
            continue
        if decl is None:
            try:
                decl = resolve_experiment(t.args["algorithm"], t.args["experiment"])[2]
            except Exception:  # noqa: BLE001 - a report of stored results: show every figure instead
                decl = False
        r = result.results.get(t.key)
        if r is not None and r["verdict"] == MEASURED:
            by_n.setdefault(t.args["robots"], []).append(r["figures"])
        elif r is not None and failed is not None:
            err = (r.get("figures") or {}).get("error") or f"verdict {r['verdict']}"
            failed[t.key] = (t.args["robots"], str(err))
    return by_n, decl or None


def _columns_of(decl, by_n: dict) -> tuple:
    """The declared columns, or every number figure as median (min-max)."""
    from swarmproof.reference_impl.protocol import ExperimentColumn

    if decl is not None and decl.columns:
        return decl.columns
    keys = sorted({k for fs in by_n.values() for f in fs for k, v in f.items()
                   if isinstance(v, (int, float)) and not isinstance(v, bool)})
    return tuple(ExperimentColumn(k, k) for k in keys)


def _g(x: float) -> str:
    """Three significant digits, without an exponent (1234.5 -> '1234')."""
    s = f"{x:.3g}"
    return f"{x:.0f}" if "e" in s else s


def _stat(col, fs: list) -> str:
    import statistics

    if col.only_if is not None:
        fs = [f for f in fs if _numbers([f.get(col.only_if)])]
    xs = _numbers(f.get(col.figure) for f in fs)
    if col.stat == "count":
        return f"{len(xs)}/{len(fs)}"
    if not xs:
        return ""
    if col.stat == "mean_sd":
        return mean_sd(xs)
    med = _g(statistics.median(xs))
    return med if col.stat == "median" else f"{med} ({_g(min(xs))}-{_g(max(xs))})"


def paper_experiment_table(result, cell_label: str) -> list[str]:
    """The lines of one experiment cell's table by team size: the trials that ran, then the
    columns its experiment declares (:class:`~swarmproof.reference_impl.protocol.ExperimentColumn`)."""
    failed: dict = {}
    by_n, decl = _trials(result, cell_label, failed)
    if not by_n and not failed:
        return ["No trial of this cell has finished yet."]
    cols = _columns_of(decl, by_n)
    about = f" ({decl.cites})" if decl is not None and decl.cites else ""
    stats = {"count": "how many trials have the figure", "median": "median",
             "median_range": "median (min-max)", "mean_sd": "mean ± sample standard deviation"}
    used = ", ".join(dict.fromkeys(stats[c.stat] for c in cols))
    only = "; ".join(f"*{c.header}* over the trials with `{c.only_if}`" for c in cols if c.only_if)
    lines = [f"Measured trials{about}, no claim judged: per team size, over its trials with the figure: {used}"
             + (f"; {only}" if only else "") + ". Seconds of tasks are in the store's `timings` table, not here.", "",
             "| robots | trials | " + ("failed | " if failed else "") + " | ".join(c.header for c in cols) + " |",
             "|---:|---:|" + ("---:|" if failed else "") + "---:|" * len(cols)]
    fails_n: dict = {}
    for n, _ in failed.values():
        fails_n[n] = fails_n.get(n, 0) + 1
    for n in sorted(set(by_n) | set(fails_n)):
        fs = by_n.get(n, [])
        lines.append(f"| {n} | {len(fs)} | " + (f"{fails_n.get(n, 0)} | " if failed else "")
                     + " | ".join(_stat(c, fs) if fs else "" for c in cols) + " |")
    if failed:
        lines += ["", f"{len(failed)} trial(s) did not run to the end (inconclusive; not in the figures above):", ""]
        lines += [f"- `{key}`: {err}" for key, (_, err) in sorted(failed.items())[:20]]
        if len(failed) > 20:
            lines.append(f"- ... and {len(failed) - 20} more (`swarmproof campaign ... --json` lists every one)")
    return lines


def plot_paper_experiment(result, cell_label: str, path: str) -> str | None:
    """The experiment's plotted figures against team size: the median over the trials, bars from
    the smallest to the largest; None when no trial finished or nothing is to be plotted."""
    import statistics

    from swarmproof.checkers.plotting import new_figure, save_png

    by_n, decl = _trials(result, cell_label)
    if not by_n:
        return None
    cols = {c.figure: c for c in _columns_of(decl, by_n)}
    keys = tuple(decl.plot) if decl is not None and decl.plot else tuple(
        k for k, c in cols.items() if c.stat != "count")[:2]
    if not keys:
        return None
    fig, ax = new_figure(6.5, 4.2)
    ax.set_aspect("auto")
    ns = sorted(by_n)
    for j, key in enumerate(keys):
        col = cols.get(key)
        xs_n, med, lo, hi = [], [], [], []
        for n in ns:
            fs = by_n[n]
            if col is not None and col.only_if is not None:
                fs = [f for f in fs if _numbers([f.get(col.only_if)])]
            xs = _numbers(f.get(key) for f in fs)
            if xs:
                m = statistics.median(xs)
                xs_n.append(n)
                med.append(m)
                lo.append(m - min(xs))
                hi.append(max(xs) - m)
        ax.errorbar(xs_n, med, yerr=[lo, hi], fmt="o-", capsize=3,
                    label=col.header if col is not None else key)
    ax.set_xticks(ns)                    # team sizes, not fractions of a robot
    ax.set_xlabel("robots")
    ax.set_ylabel("median over trials (bars: min-max)")
    ax.legend(fontsize=8)
    ax.set_title(cell_label, fontsize=10)
    return save_png(fig, path)


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
    k = 0
    for c in result.cells():
        if c["kind"] == "experiment":
            rel = os.path.join("plots", f"experiment-{k}.png")
            k += 1
            os.makedirs(os.path.join(result.out_dir, "plots"), exist_ok=True)
            if plot_paper_experiment(result, c["cell"], os.path.join(result.out_dir, rel)):
                plots[c["cell"]] = rel
    return atomic_write_text(os.path.join(result.out_dir, "report.md"), markdown(result, plots))
