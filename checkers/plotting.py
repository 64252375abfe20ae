"""Shared plotting helpers: matplotlib on the Agg backend, PNGs written atomically.

Every picture swarmproof draws (formations, trajectories, counterexamples,
lattice checks) goes through :func:`new_figure` and :func:`save_png` so that
output is deterministic (no timestamps in the PNG metadata) and never
half-written.
"""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")  # no screen here, nor in CI
import matplotlib.pyplot as plt  # noqa: E402

from swarmproof.models.fileio import atomic_write_bytes  # noqa: E402

__all__ = ["new_figure", "save_png", "ROLE_COLORS", "plt"]

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
    buf = io.BytesIO()
    fig.savefig(buf, format="png", metadata={"Software": None}, bbox_inches="tight")
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())
