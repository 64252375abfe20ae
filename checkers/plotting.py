"""Shared plotting helpers: matplotlib on the Agg backend, PNGs and GIFs written atomically.

Every picture swarmproof draws (formations, trajectories, counterexamples,
lattice checks) goes through :func:`new_figure` and :func:`save_png` so that
output is deterministic (no timestamps in the PNG metadata) and never
half-written.  Animations (:func:`animate_trace`, a counterexample as an
animated GIF) go through :func:`save_gif`: Agg renders each frame (the axes
once, then only the artists that move), Pillow encodes the GIF as matplotlib's
``PillowWriter`` does (no timestamps either), and the bytes are written atomically.
"""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")  # no screen here, nor in CI
import matplotlib.pyplot as plt  # noqa: E402

from swarmproof.models.fileio import atomic_write_bytes, check_output_path  # noqa: E402

__all__ = ["new_figure", "save_png", "save_gif", "animate_trace", "gif_frames", "ROLE_COLORS", "plt"]

#: A colour per role index (cycled), colour-blind friendly (Okabe-Ito).
ROLE_COLORS = ("#0072B2", "#E69F00", "#009E73", "#CC79A7", "#56B4E9", "#D55E00",
               "#F0E442", "#000000")


def new_figure(width: float = 7.0, height: float = 7.0):
    """A new ``(figure, axes)`` pair with equal aspect."""
    fig, ax = plt.subplots(figsize=(width, height), dpi=100)
    ax.set_aspect("equal")
    return fig, ax


def save_png(fig, path) -> str:
    """Render ``fig`` to PNG (no metadata, so bit-identical reruns) and write atomically."""
    check_output_path(path)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None}, bbox_inches="tight")
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def save_gif(fig, update, frames, path, *, fps: int = 8, animated=()) -> str:
    """Render ``update(frame)`` for every frame and encode the frames as a GIF with Pillow (as
    matplotlib's ``PillowWriter`` does); write atomically.

    ``update`` changes the figure's artists for one frame.  ``animated``: the artists ``update``
    changes, when it changes no other (it may also hide them).  The rest of the figure (axes,
    ticks, labels) is then drawn once and each frame redraws only those artists on it; that is the
    picture of a whole redraw when every other artist of their axes lies below them (lower
    ``zorder``) or apart from them (the ticks and spines around the data).  The figure is closed
    afterwards.  Same figure and frames give the same bytes.
    """
    from PIL import Image

    from swarmproof.models.fileio import atomic_write_bytes

    check_output_path(path)     # a missing folder is refused, as for every output (never created)
    try:
        images = []
        canvas = fig.canvas
        if animated:
            for a in animated:
                a.set_animated(True)
            canvas.draw()                             # everything but the animated artists, once
            background = canvas.copy_from_bbox(fig.bbox)
            order = _draw_order(animated)
        for f in frames:
            update(f)
            if animated:
                canvas.restore_region(background)
                for a in order:
                    fig.draw_artist(a)
                rgba = bytes(canvas.buffer_rgba())
            else:                                     # the whole figure, as PillowWriter grabs it
                raw = io.BytesIO()
                fig.savefig(raw, format="rgba", dpi=fig.dpi)
                rgba = raw.getvalue()
            im = Image.frombuffer("RGBA", canvas.get_width_height(), rgba, "raw", "RGBA", 0, 1)
            # as PillowWriter: an opaque frame goes to the GIF encoder as RGB (a better palette)
            images.append(im if im.getextrema()[3][0] < 255 else im.convert("RGB"))
        buf = io.BytesIO()
        images[0].save(buf, format="GIF", save_all=True, append_images=images[1:], duration=int(1000 / fps),
                       loop=0)
    finally:
        plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def _draw_order(artists) -> list:
    """``artists`` in the order their axes draw them: by ``zorder``, ties in the axes' own order."""
    def key(a):
        kids = a.axes.get_children() if a.axes is not None else []
        return (a.get_zorder(), kids.index(a) if a in kids else len(kids))
    return sorted(artists, key=key)


def gif_frames(steps: int, mark: int | None = None, max_frames: int = 60, hold: int = 6) -> list:
    """The recorded frames shown: ``max_frames`` evenly spaced over ``0..steps`` (the last frame
    index; on a dense trace the last step), always the first, the last and ``mark`` (the
    violation's frame), which is held for ``hold`` frames.

    >>> gif_frames(10, mark=7, max_frames=4, hold=2)
    [0, 3, 7, 7, 10]
    >>> gif_frames(0)
    [0, 0]
    """
    import numpy as np

    picks = set(np.linspace(0, steps, min(max_frames, steps + 1)).round().astype(int).tolist()) | {0, steps}
    if mark is not None and 0 <= mark <= steps:
        picks.add(int(mark))
    out = []
    for t in sorted(picks):
        out += [t] * (hold if t == mark else 1)
    if len(out) < 2:  # a GIF of a single frame does not animate
        out.append(out[-1])
    return out


def animate_trace(trace, path, *, phi: float | None = None, mark_step: int | None = None, title: str = "",
                  mark_label: str = "violation", mark_ids=None, max_frames: int = 40, fps: int = 8) -> str:
    """An animated GIF of a trace: each robot's trail so far, its position, heading and ID, the
    communication links (pairs closer than ``phi``) and, at ``mark_step``, the robots
    ``mark_ids`` (default: every present robot) circled in red (the violation).
    A sparse trace (``trace.times``) shows the frames it kept, captioned by their engine steps; a
    ``mark_step`` it did not keep is not marked.  Deterministic: same trace, same bytes.
    """
    import numpy as np

    P = np.asarray(trace.poses, float)
    # frames index the arrays; the caption names engine steps (they differ on a sparse trace)
    last, T, n = trace.frames - 1, trace.steps, trace.n
    mark = None if mark_step is None else trace.frame_of(mark_step)
    xy = P[:, :, :2].reshape(-1, 2)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.1 * float(max(hi - lo)) + 0.3
    fig, ax = new_figure(4.5, 4.5)
    fig.set_dpi(80)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    trails = [ax.plot([], [], lw=0.8, color="0.65", zorder=1)[0] for _ in range(n)]
    links = ax.plot([], [], lw=0.6, color="tab:green", alpha=0.6, zorder=1)[0]
    dots = ax.plot([], [], "o", ms=6, color="tab:blue", zorder=3)[0]
    heads = ax.quiver(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), angles="xy", scale_units="xy",
                      scale=1.0, width=0.006, color="tab:blue", zorder=3)
    ring = ax.plot([], [], "o", ms=13, mfc="none", mew=1.5, color="tab:red", zorder=4)[0]
    labels = [ax.text(0, 0, str(int(trace.ids[k])), fontsize=7, zorder=5) for k in range(n)]
    caption = ax.set_title(title, fontsize=9)
    size = 0.08 * float(max(hi - lo) + 2 * pad)

    def update(t: int) -> None:
        pres = trace.present_at(t)
        for k in range(n):
            trails[k].set_data(P[: t + 1, k, 0], P[: t + 1, k, 1])
            labels[k].set_position((P[t, k, 0] + 0.03, P[t, k, 1] + 0.03))
            labels[k].set_visible(bool(pres[k]))
        dots.set_data(P[t, pres, 0], P[t, pres, 1])
        u = np.where(pres, size * np.cos(P[t, :, 2]), 0.0)
        v = np.where(pres, size * np.sin(P[t, :, 2]), 0.0)
        heads.set_offsets(P[t, :, :2])
        heads.set_UVC(u, v)
        lx, ly = [], []
        if phi is not None:
            idx = np.flatnonzero(pres)
            for a in range(len(idx)):
                for b in range(a + 1, len(idx)):
                    pa, pb = P[t, idx[a], :2], P[t, idx[b], :2]
                    if float(np.hypot(*(pa - pb))) < phi:
                        lx += [pa[0], pb[0], np.nan]
                        ly += [pa[1], pb[1], np.nan]
        links.set_data(lx, ly)
        marked = mark is not None and t == mark
        sel = pres if mark_ids is None else pres & np.isin(trace.ids, list(mark_ids))
        ring.set_data(P[t, sel, 0] if marked else [], P[t, sel, 1] if marked else [])
        step = trace.time_of(t)
        text = f"{title}  step {step}/{T}" if title else f"step {step}/{T}"
        caption.set_text(text + (f": {mark_label}" if marked else ""))
        caption.set_color("tab:red" if marked else "black")

    # every artist update() changes lies above the axes' own (ticks and spines, apart from the data)
    return save_gif(fig, update, gif_frames(last, mark, max_frames), path, fps=fps,
                    animated=[*trails, links, dots, heads, ring, *labels, caption])


def plot_pattern_check(result, path) -> str:
    """Draw a repeating pattern's assembled copies (002 Defs. 3, 7): each copy of B as a polygon
    of its points, copy heads as squares, the vectors of A from the origin as arrows, and an
    overlap (if any) as a red ring.  Returns the path written."""
    import numpy as np

    pattern = result.pattern
    b = len(pattern.basic)
    pts = pattern.formation(result.copies * b)
    fig, ax = new_figure()
    for k in range(0, len(pts), b):
        copy = pts[k:k + b]
        color = ROLE_COLORS[(k // b) % len(ROLE_COLORS)]
        if b > 1:
            closed = np.vstack((copy, copy[:1])) if b > 2 else copy
            ax.plot(closed[:, 0], closed[:, 1], "-", color=color, lw=1.0, alpha=0.7)
        ax.plot(copy[:, 0], copy[:, 1], "o", color=color, ms=4)
        ax.plot(copy[0, 0], copy[0, 1], "s", color="black", ms=3)
    for ax_, ay_ in pattern.assembling:
        if (ax_, ay_) != (0.0, 0.0):
            ax.annotate("", xy=(ax_, ay_), xytext=(0, 0), arrowprops={"arrowstyle": "->", "color": "grey", "lw": 1.2})
    if result.overlap:
        x, y = result.overlap["at"]
        ax.plot([x], [y], "o", ms=16, mfc="none", mec="red", mew=2)
    ax.set_title(f"{pattern.name}: {result.copies} copies of B ({len(pts)} points), {result.status}", fontsize=10)
    return save_png(fig, path)
