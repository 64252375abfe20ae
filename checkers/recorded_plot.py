"""Pictures of a judged recorded run: trajectories with the graph at the violation, and an animation.

:func:`plot_recorded` draws every robot's trajectory (the instants the report kept), the robots
at the *focus* instant -- the first violation's (a collision: the step it starts), else the
log's last -- with their communication links (closer than phi), their parent links, the
components of a split graph in their own colours, and the robots a violation names circled in
red.  :func:`gif_recorded` animates the kept instants with the focus held.  Matplotlib's Agg
backend; the same report gives the same bytes.
"""

from __future__ import annotations

import numpy as np

from swarmproof.checkers.plotting import ROLE_COLORS, animate_trace, new_figure, save_png
from swarmproof.checkers.recorded import aligned_frames, fmt_s
from swarmproof.models.trace import Trace

__all__ = ["plot_recorded", "gif_recorded", "focus_of"]


def focus_of(rep):
    """``(instant, property name, robot ids)`` of the first violation (by instant), else the last instant."""
    best = None
    for name, r in rep.results.items():
        w = r.witness or {}
        if r.status != "violated" or not isinstance(w.get("step"), (int, np.integer)):
            continue
        k = int(w.get("instant", w["step"]))          # where it first shows (checkers.recorded.shown_at)
        robots = list(w.get("robots") or []) + [w[x] for x in ("child", "parent", "robot") if x in w]
        comps = sorted(w.get("components") or [], key=len)
        robots += [r for c in comps[:-1] for r in c]        # a split: the robots cut off from the largest part
        if best is None or k < best[0]:
            best = (min(k, rep.clock.instants - 1), name, [int(x) for x in robots])
    return best or (rep.clock.instants - 1, None, [])


def _frames(rep, extra: int):
    kept = {k: (p, q, f, pr) for k, p, q, f, pr in rep.frames}
    if extra not in kept:
        kept[extra] = _frame_at(rep, extra)
    return dict(sorted(kept.items()))


def _frame_at(rep, k: int):
    """The aligned frame at instant ``k`` (computed alone: one chunk of one instant)."""
    from dataclasses import replace

    clock = replace(rep.clock, start_ns=rep.clock.start_ns + k * rep.clock.period_ns, instants=1)
    for _, poses, pars, fresh, present, _ in aligned_frames(rep.log, clock, chunk=1):
        return poses.copy(), None if pars is None else pars.copy(), fresh.copy(), present.copy()


def plot_recorded(rep, path) -> str:
    from swarmproof.invariants.connectivity import components
    from swarmproof.models.sensing import neighbor_pairs

    k, name, marked = focus_of(rep)
    frames = _frames(rep, k)
    ids = rep.ids
    P = np.stack([f[0] for f in frames.values()])
    fig, ax = new_figure()
    for j in range(len(ids)):
        ax.plot(P[:, j, 0], P[:, j, 1], lw=0.6, color="0.75", zorder=1)
    poses, pars, fresh, present = frames[k]
    xy = poses[:, :2]
    i, jj, _ = neighbor_pairs(xy, rep.phi)
    for a, b in zip(i, jj):
        ax.plot([xy[a, 0], xy[b, 0]], [xy[a, 1], xy[b, 1]], color="tab:green", lw=0.6, alpha=0.6, zorder=2)
    slot = {rid: s for s, rid in enumerate(ids)}
    if pars is not None:
        for s, par in enumerate(pars):
            if par >= 0 and int(par) in slot:
                q = slot[int(par)]
                ax.plot([xy[s, 0], xy[q, 0]], [xy[s, 1], xy[q, 1]], color="0.15", lw=1.3, zorder=2)
    comps = sorted(components(len(ids), i, jj), key=lambda c: min(c))
    for ci, comp in enumerate(comps):
        sel = sorted(comp)
        color = ROLE_COLORS[ci % len(ROLE_COLORS)] if len(comps) > 1 else "tab:blue"
        ax.scatter(xy[sel, 0], xy[sel, 1], s=36, color=color, edgecolors="black", linewidths=0.5, zorder=3)
    stale = [s for s in range(len(ids)) if present[s] and not fresh[s]]
    if stale:
        ax.scatter(xy[stale, 0], xy[stale, 1], s=80, marker="x", color="0.4", zorder=4, label="stale sample")
    ring = [slot[r] for r in marked if r in slot]
    if ring:
        ax.scatter(xy[ring, 0], xy[ring, 1], s=220, facecolors="none", edgecolors="tab:red", linewidths=1.8, zorder=5)
    for s, rid in enumerate(ids):        # beside the ring a violation draws, not under it
        ax.annotate(str(rid), (xy[s, 0], xy[s, 1]), xytext=(7, 7), textcoords="offset points", fontsize=7)
    # a log along a line keeps some height: pad the shorter side to a third of the longer
    allxy = P[:, :, :2].reshape(-1, 2)
    lo, hi = allxy.min(axis=0), allxy.max(axis=0)
    span = max(float(np.max(hi - lo)), rep.phi)
    mid = (lo + hi) / 2
    half = np.maximum((hi - lo) / 2, span / 6) + 0.1 * span
    ax.set_xlim(mid[0] - half[0], mid[0] + half[0])
    ax.set_ylim(mid[1] - half[1], mid[1] + half[1])
    if len(comps) > 1:
        ax.scatter([], [], s=36, color=ROLE_COLORS[0], edgecolors="black", linewidths=0.5,
                   label=f"{len(comps)} components (colours)")
    when = f"{fmt_s(rep.clock.seconds(k))} s (instant {k})"
    status = {n: r.status for n, r in rep.results.items()}
    head = f"{name} violated at {when}" if name else f"end of log, {when}"
    ax.set_title(f"{rep.log.path.rstrip('/').split('/')[-1]}: {len(ids)} robots; {head}\n"
                 + ", ".join(f"{n} {s}" for n, s in status.items()), fontsize=8)
    if stale or len(comps) > 1:
        ax.legend(loc="best", fontsize=7)
    return save_png(fig, path)


def gif_recorded(rep, path) -> str:
    k, name, marked = focus_of(rep)
    frames = _frames(rep, k)
    steps = list(frames)
    # a robot that has not reported yet is not drawn (present), as the engine's robots added later
    trace = Trace(ids=np.asarray(rep.ids), poses=np.stack([f[0] for f in frames.values()]),
                  states=[tuple(() for _ in rep.ids)] * len(steps), times=steps,
                  present=np.stack([f[3] for f in frames.values()]), meta={"status": "recorded"})
    return animate_trace(trace, path, phi=rep.phi, mark_step=k if name else None, mark_ids=marked or None,
                         title=f"{name} violated" if name else "recorded run", mark_label=f"{name} at {fmt_s(rep.clock.seconds(k))} s",
                         max_frames=120)
