"""Lee & Chong's Algorithm 4 numbering of neighbors, as a pure function of IDs (003 Sec. 4.1).

Shared by the controller (:mod:`.algorithm`) and the exact checks (:mod:`.checks`).

>>> neighbor_id(5, "uni"), neighbor_id(2, "uni"), neighbor_id(7, "multi", 3)
(3, 0, 6)
"""

from __future__ import annotations

__all__ = ["neighbor_id"]


def neighbor_id(robot_id: int, kind: str, k: int | None = None) -> int:
    """003 Alg. 4: N_id of the robot with ID ``robot_id`` for a uni-line (``kind="uni"``) or a
    multi-line pattern of ``k`` lines (``NoLine := k``, line 7).

    Uni-line: ``ID - 2`` for ``ID > 2``, else 0.  Multi-line: ``LiOrder = ID % NoLine``;
    ``ID - NoLine`` when ``LiOrder = 0``, else ``ID - floor((LiOrder + 1) / 2)`` ("the quotient
    from the division of ... LiOrder plus one, by ... 2", Sec. 4.1).
    """
    if kind == "uni":
        return robot_id - 2 if robot_id > 2 else 0
    no_line = int(k)
    li_order = robot_id % no_line
    if li_order == 0:
        return robot_id - no_line
    return robot_id - (li_order + 1) // 2
