"""``swarmproof replay``: re-run a counterexample file and judge its property again.

Exit codes: 1 while the counterexample still reproduces (the property is
violated again), 0 once it no longer does, 2 unreadable or malformed file.
"""

from __future__ import annotations

from swarmproof.commands import emit_json, human

NAME = "replay"
HELP = "re-run a swarmproof-counterexample/1 file; exit 1 while it reproduces, 0 once it does not"
DESCRIPTION = __doc__.split("\n\n", 1)[1] if __doc__ else HELP


def add_arguments(p) -> None:
    p.add_argument("file", metavar="FILE", help="a swarmproof-counterexample/1 file (swarmproof explore --out)")
    p.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    p.add_argument("--plot", metavar="PNG", help="draw the trajectories with the violation marked")
    p.add_argument("--gif", metavar="GIF", help="animate the replayed run (animated GIF), the violation step marked")


def plot_replay(rr, path) -> str:
    """Trajectories of the replayed run, start (o) and end (x) of each robot, the violation step marked."""
    from swarmproof.checkers.plotting import new_figure, save_png

    trace = rr.result.trace
    fig, ax = new_figure()
    step = rr.step
    for k in range(trace.n):
        ax.plot(trace.poses[:, k, 0], trace.poses[:, k, 1], lw=0.8, color="0.6", zorder=1)
        ax.plot(trace.poses[0, k, 0], trace.poses[0, k, 1], "o", ms=4, color="tab:blue", zorder=2)
        ax.plot(trace.poses[-1, k, 0], trace.poses[-1, k, 1], "x", ms=5, color="0.2", zorder=2)
        ax.annotate(str(int(trace.ids[k])), trace.poses[0, k, :2], fontsize=7, zorder=3)
    if step is not None and 0 <= int(step) <= trace.steps:
        s = int(step)
        pres = trace.present_at(s)
        ax.plot(trace.poses[s, pres, 0], trace.poses[s, pres, 1], "o", ms=7, mfc="none", color="tab:red",
                zorder=4, label=f"step {s}: violation")
        ax.legend(loc="best", fontsize=8)
    cx = rr.counterexample
    status = "reproduced" if rr.reproduced else "not reproduced"
    ax.set_title(f"{cx.algorithm} {cx.property} ({status})", fontsize=10)
    ax.set_aspect("equal")
    return save_png(fig, path)


def gif_replay(rr, path) -> str:
    """The replayed run as an animated GIF (:func:`swarmproof.checkers.plotting.animate_trace`)."""
    from swarmproof.checkers.plotting import animate_trace

    cx = rr.counterexample
    status = "reproduced" if rr.reproduced else "not reproduced"
    w = rr.verdict.witness or {}
    named = [w[k] for k in ("robot", "child", "parent", "relocate", "root") if isinstance(w.get(k), int)]
    named += [int(i) for i in w.get("robots", ()) if isinstance(i, int)]
    return animate_trace(rr.result.trace, path, phi=float(cx.params["range"]),
                         mark_step=None if rr.step is None else int(rr.step), mark_ids=named or None,
                         title=f"{rr.result.trace.meta.get('algorithm', cx.algorithm)} {cx.property} ({status})")


def run(args) -> int:
    from swarmproof.checkers.replay import replay_file
    from swarmproof.models.fileio import check_output_path

    if args.plot is not None:
        check_output_path(args.plot, "--plot")
    if args.gif is not None:
        check_output_path(args.gif, "--gif", new_folder=True)     # the GIF writer creates its folder
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
    return 1 if rr.reproduced else 0
