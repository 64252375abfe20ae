"""Sensing: what a robot perceives, and the Observation it gets (issue 12).

``RobotModel.sensing``: ``"local"`` (IDs and body-frame poses of the robots in range),
``"global"`` (additionally the own pose in the common frame), ``"anonymous"``
(body-frame positions of every robot, no IDs, no headings).
"""

from __future__ import annotations

import functools

import numpy as np

from swarmproof.models.errors import UsageError
from swarmproof.models.se2 import wrap_angle
from swarmproof.models.sensing import neighbor_pairs

from ..protocol import Observation


def _rel_rows(frames: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Row-wise ``frames[k]^-1 @ poses[k]`` (same formulas as ``se2.relative_many``)."""
    c = np.cos(frames[:, 2])
    s = np.sin(frames[:, 2])
    dx = poses[:, 0] - frames[:, 0]
    dy = poses[:, 1] - frames[:, 1]
    out = np.empty_like(poses)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = wrap_angle(poses[:, 2] - frames[:, 2])
    return out


@functools.lru_cache(maxsize=256)
def _all_pairs(m: int) -> tuple:
    """``(src, dst)``: every ordered pair of distinct rows of ``m``, row-major (anonymous sensing
    senses every robot); read-only, built once per team size instead of every step."""
    ii, jj = np.meshgrid(np.arange(m), np.arange(m), indexing="ij")
    mask = ii != jj
    src, dst = ii[mask], jj[mask]
    src.setflags(write=False)
    dst.setflags(write=False)
    return src, dst


_OBS_FIELDS = ("step", "robot_id", "neighbor_ids", "neighbor_poses", "messages", "own_pose")


def _new_observation(step, robot_id, neighbor_ids, neighbor_poses, messages, own_pose) -> Observation:
    """Build a frozen Observation without the dataclass ``__init__`` overhead (hot path).

    Equivalent to ``Observation(step, robot_id, ...)``: the object is the same
    frozen dataclass (assignment still raises), only its fields are filled directly.
    """
    obs = object.__new__(Observation)
    d = obs.__dict__
    d["step"] = step
    d["robot_id"] = robot_id
    d["neighbor_ids"] = neighbor_ids
    d["neighbor_poses"] = neighbor_poses
    d["messages"] = messages
    d["own_pose"] = own_pose
    return obs


def sense(pp, idx, ids, pres_ids, phi: float, *, inclusive: bool, anonymous: bool, noise, t: int, rng):
    """One step's sensing of the present robots (``pp``: their poses, slot order ``idx``).

    Returns ``(nb_ids, nb_slots, nb_rel)``: per present robot, the sensed robots' IDs
    (increasing; anonymous: every robot, by body-frame ``(x, y)``), their slots, and
    their read-only body-frame poses.  ``noise``: a fault model whose ``noise_std`` and
    ``sensing_noise`` perturb the sensed poses (drawn from ``rng``), or None.
    """
    m = len(idx)
    if anonymous:
        src, dst = _all_pairs(m)
        rel = _rel_rows(pp[src], pp[dst])
        order = np.lexsort((rel[:, 1], rel[:, 0], src))
    else:
        i, j, _ = neighbor_pairs(pp[:, :2], phi, inclusive)
        src = np.concatenate((i, j))
        dst = np.concatenate((j, i))
        order = np.lexsort((pres_ids[dst], src))
        rel = None
    src = src[order]
    dst = dst[order]
    rel = _rel_rows(pp[src], pp[dst]) if rel is None else rel[order]
    off = np.zeros(m + 1, dtype=np.intp)
    np.cumsum(np.bincount(src, minlength=m), out=off[1:])
    if noise is not None:
        std_xy, std_th = (float(x) for x in noise.noise_std)
        for a in range(m):
            lo, hi = off[a], off[a + 1]
            if hi == lo:
                continue
            block = rel[lo:hi]
            if std_xy > 0 or std_th > 0:
                block = block + np.column_stack((
                    rng.normal(0.0, std_xy, (hi - lo, 2)) if std_xy > 0 else np.zeros((hi - lo, 2)),
                    rng.normal(0.0, std_th, hi - lo) if std_th > 0 else np.zeros(hi - lo)))
                block[:, 2] = wrap_angle(block[:, 2])
            if noise.sensing_noise is not None:
                block = np.asarray(noise.sensing_noise(t, int(pres_ids[a]), block.copy(), rng), dtype=float)
                if block.shape != (hi - lo, 3):
                    raise UsageError(f"faults.sensing_noise returned shape={block.shape!r}, "
                                     f"expected ({hi - lo}, 3)")
            rel[lo:hi] = block
    rel.setflags(write=False)
    dst_slots = idx[dst]
    dst_ids = ids[dst_slots].tolist()
    dst_slots_l = dst_slots.tolist()
    off_l = off.tolist()
    nb_ids = [tuple(dst_ids[off_l[a]:off_l[a + 1]]) for a in range(m)]
    nb_slots = [dst_slots_l[off_l[a]:off_l[a + 1]] for a in range(m)]
    nb_rel = [rel[off_l[a]:off_l[a + 1]] for a in range(m)]
    return nb_ids, nb_slots, nb_rel
