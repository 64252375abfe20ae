"""Song & O'Kane 2016: forming repeating lattice patterns, provably (reference implementation).

The algorithm of 001_7a4e517b856331bc.txt Sec. V, line by line:

* every robot is *stable* or *unstable* (Sec. V-A); the highest-ID robot
  becomes stable with role v0 once the communication timeout (Def. 10) has
  passed since its known highest ID last changed (Sec. V-B);
* a stable robot's *vacancies* (Def. 9) are the out-edges of its role whose
  pose holds no stable robot; the first one in out-edge order is its *most
  important vacancy* (docs/decisions.md, "## song2016");
* every robot broadcasts the message of Table I, computed by Algorithm 1
  (:func:`compute_message`, line numbers in comments), with the path lists
  that stop the "rumor problem";
* the root is the highest-ID stable robot with a vacancy, the relocate robot
  the highest-ID unstable robot; parents are chosen as Sec. V-B says
  (:func:`get_parent_msg`), and the "subtree" marker (line 29) tells the
  robots of the moving subtree;
* motion (Sec. V-C, No Child Left Behind): the relocate robot moves toward
  its parent, or toward the vacancy when its parent is the root; every other
  robot of the moving subtree moves toward its parent when farther than the
  safe distance d_s; every moving robot ends its step inside the intersection
  of its children's bounded ranges (Def. 8), and does not move when that
  safe region is empty;
* the relocate robot becomes stable on reaching the vacancy (within an
  epsilon, footnote 2, then turned to the vacancy's orientation, Sec. V-A);
* the run ends when no unstable robot remains (:meth:`Song2016.finished`).

The mapping paper item -> function is the table in docs/song2016.md; every
choice where the paper is silent is in docs/decisions.md ("## song2016").

Controller state
----------------
:meth:`Song2016Controller.state` returns a tuple of ``(key, value)`` pairs,
always in this order (JSON-friendly: bools, ints, strs, floats, tuples, None):

``stable`` (bool), ``role`` (role name or None), ``parent`` (ID or None, the
spanning-tree parent chosen this step, Algorithm 1 line 28), ``children``
(sorted tuple of the IDs whose last message named this robot as parent: the
children whose bounded ranges formed this step's safe region), ``relocate``
(bool: this robot is the confirmed relocate robot), ``subtree`` (bool, Table I
"subtree"), ``moving`` (bool: this step's command translates the robot),
``goal`` (body-frame ``(x, y)`` of the goal of this step: the parent or the
vacancy, else None), ``target`` (body-frame ``(x, y)`` where the command ends
the step: inside the safe region when ``moving``; else None),
``safe_radius`` (float, ``phi - v*dt`` shrunk by
:data:`~swarmproof.reference_impl.song2016.geometry.SAFE_MARGIN`),
``highest_id``/``highest_since``, ``root_id``, ``relocate_id``/``relocate_since``
(the principal information and the step at which it last changed, which
drive the communication timeouts), ``mover``/``mover_since`` (``"relocate"``,
``"subtree"`` or None, and since when: the movement timeout) and
``vacancy`` (the most important vacancy of this robot when stable, as
``(x, y, theta, role, edge)`` in its body frame, else None).

References
----------
001_7a4e517b856331bc.txt: Sec. III-A (model), Defs. 1-6, Sec. III-C-2 (Q),
Lemma 7, Def. 8, Sec. V-A (Def. 9), Sec. V-B (Table I, Def. 10, Algorithm 1),
Sec. V-C (NCLB), Lemmas 11-12, Theorem 13, Sec. VI (experiments).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Hashable, Iterable, Mapping, Sequence

import numpy as np

from swarmproof.models.errors import ProtocolError, UsageError, check_finite
from swarmproof.models.se2 import wrap_angle
from ..protocol import (Assumption, Command, Observation, Params, ParamSpec, RobotModel, VerifyPlan,
                        connected_start)
from .geometry import (SAFE_MARGIN, bounded_range_radius, closest_point_in_discs,
                                farthest_point_toward, in_discs, reachable_point)

__all__ = [
    "Vacancy", "Song2016Message", "Song2016Config", "Song2016", "Song2016Controller",
    "vacancies", "vacancy_in_observer_frame", "compute_message", "get_parent_msg",
    "sequential_fill", "RUMOR_FILTERS", "PARENT_RULES", "Song2016Literal",
    "Song2016SubtreeClock", "Song2016SubtreeClockController",
]

#: The two readings of the rumor rule (docs/decisions.md, "## song2016"):
#: ``"message"`` is Algorithm 1 line 12 as printed (a message whose
#: pathFromRoot *or* pathFromRelocate contains my ID is ignored entirely);
#: ``"field"`` is the prose of Sec. V-B ("a robot rejects information for which
#: its own ID appears in the pathFromRoot or pathFromRelocate lists") read per
#: field: root information is ignored when my ID is in pathFromRoot, relocate
#: information when my ID is in pathFromRelocate.
RUMOR_FILTERS = ("message", "field")

#: The readings of the parent rule (docs/decisions.md, "## song2016", "Relocate
#: robot's parent"). The paper states the rule twice:  Sec. V-B ("chooses for its
#: parent [...] the stable neighbor that is the fewest hops from the root") and the
#: proof of Lemma 12 ("selects the neighbor with 1) the shortest path to root, 2) the
#: highest ID"), and describes the relocate robot's route as "its path to the root"
#: (after Lemma 11; proof of Theorem 13).
#:
#: * ``"relocate_route"`` (default): Sec. V-B for every robot except the relocate
#:   robot, whose parent is Lemma 12's (the neighbor on its shortest path to the
#:   root), the one reading under which all of these sentences hold;
#: * ``"stable_first"``: Sec. V-B for every robot, the relocate robot included
#:   (it deadlocks: docs/song2016.md, "What the implementation found");
#: * ``"fewest_hops"``: Lemma 12's rule for every robot.
PARENT_RULES = ("relocate_route", "stable_first", "fewest_hops")


# ---------------------------------------------------------------------------
# Data: vacancies and messages (Def. 9, Table I)
# ---------------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class Vacancy:
    """A vacancy ``(p_hat, w)`` of a stable robot (001 Def. 9).

    Attributes
    ----------
    x, y, theta : float
        The pose p_hat in the body frame of the stable robot that owns it
        (the transform ``T(e)`` of out-edge ``e``).
    role : str
        The role vertex ``w`` (the target of ``e``), the role the robot that
        fills the vacancy takes.
    edge : int
        The index of ``e`` in the lattice graph (its out-edge order ranks
        vacancies).
    """

    x: float
    y: float
    theta: float
    role: str
    edge: int

    def as_tuple(self) -> tuple:
        """``(x, y, theta, role, edge)``."""
        return (self.x, self.y, self.theta, self.role, self.edge)


@dataclass(frozen=True, slots=True)
class Song2016Message:
    """The message of 001 Table I, field by field (snake_case names).

    ``None`` stands for the paper's ``-inf`` (Algorithm 1 lines 6-7): no root
    known, no unstable robot known.

    Attributes
    ----------
    sender_id : int
        senderID: ID of the robot that sent this message.
    highest_id : int
        highestID: highest robot ID in the system (as far as the sender knows).
    root_id : int or None
        rootID: ID of the root robot (highest-ID stable robot with a vacancy).
    relocate_id : int or None
        relocateID: ID of the relocate robot (highest-ID unstable robot).
    parent_id : int or None
        parentID: ID of the sender's spanning-tree parent (None for the root
        and for robots that know no root).
    vacancy : Vacancy or None
        vacancy: the most important vacancy of the root robot, in the root's
        body frame.
    subtree : bool
        subtree: whether the sender is in the subtree rooted at the relocate
        robot.
    stable : bool
        stable: whether the sender is stable.
    path_from_root : tuple of int
        pathFromRoot: IDs on the shortest path from the root to the sender.
    path_from_relocate : tuple of int
        pathFromRelocate: IDs on the shortest path from the relocate robot to
        the sender.
    """

    sender_id: int
    highest_id: int
    root_id: int | None
    relocate_id: int | None
    parent_id: int | None
    vacancy: Vacancy | None
    subtree: bool
    stable: bool
    path_from_root: tuple[int, ...]
    path_from_relocate: tuple[int, ...]

    def as_dict(self) -> dict:
        """A JSON-friendly dict (Table I names in snake_case)."""
        return {
            "sender_id": self.sender_id, "highest_id": self.highest_id,
            "root_id": self.root_id, "relocate_id": self.relocate_id,
            "parent_id": self.parent_id,
            "vacancy": None if self.vacancy is None else list(self.vacancy.as_tuple()),
            "subtree": self.subtree, "stable": self.stable,
            "path_from_root": list(self.path_from_root),
            "path_from_relocate": list(self.path_from_relocate),
        }


# ---------------------------------------------------------------------------
# Definition 9: vacancies, and their transformation into the observer's frame
# ---------------------------------------------------------------------------

def vacancies(out_edges: Sequence[tuple[float, float, float, str, int]],
              stable_neighbor_xy: Iterable[tuple[float, float]],
              tolerance: float) -> tuple[Vacancy, ...]:
    """The vacancies of a stable robot, in out-edge order (001 Def. 9).

    "For each out-edge e of u in the lattice graph, there is a pose p_hat,
    relative to u, corresponding to the vertex w. If there is no stable robot
    at p_hat, then (p_hat, w) is a vacancy of r_s. (If, by chance, there is an
    unstable robot at p_hat, we still consider (p_hat, w) a vacancy of r_s.)"

    Parameters
    ----------
    out_edges : sequence of (x, y, theta, target_role, edge_index)
        The out-edges of the robot's role vertex, in lattice order.
    stable_neighbor_xy : iterable of (x, y)
        Body-frame positions of the neighbors whose last message said
        ``stable`` (only stable robots fill a vacancy).
    tolerance : float
        A stable robot within this distance of p_hat fills it (footnote 2:
        half the smallest correct distance between final positions).

    Returns
    -------
    tuple of Vacancy
        The first is the most important vacancy (docs/decisions.md).

    Examples
    --------
    >>> sq = [(1.0, 0.0, 0.0, "A", 0), (0.0, 1.0, 0.0, "A", 1),
    ...       (-1.0, 0.0, 0.0, "A", 2), (0.0, -1.0, 0.0, "A", 3)]
    >>> [v.edge for v in vacancies(sq, [(1.0, 1e-9)], 0.5)]
    [1, 2, 3]

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-A, Definition 9.
    """
    occupied = list(stable_neighbor_xy)
    tol2 = tolerance * tolerance
    out = []
    for x, y, th, role, idx in out_edges:
        filled = False
        for ox, oy in occupied:
            dx, dy = ox - x, oy - y
            if dx * dx + dy * dy <= tol2:
                filled = True
                break
        if not filled:
            out.append(Vacancy(x, y, th, role, idx))
    return tuple(out)


def vacancy_in_observer_frame(observed_owner: Sequence[float], vacancy: Vacancy
                              ) -> tuple[float, float, float]:
    """A vacancy of r_s expressed in the body frame of an observer r_i (001 Sec. V-A).

    r_s computes the vacancy pose p_hat^(s) in its body frame; r_i observes
    r_s at p_s^(i) = (x, y, theta) in its own.  The vacancy in r_i's frame
    is the composition ``p_s^(i) o p_hat^(s)``: position
    ``M_s^(i) [x_hat^(s), y_hat^(s), 1]^T`` and heading
    ``theta_hat^(i) = theta_hat^(s) + theta_s^(i)`` (as printed).  The paper
    prints the matrix product as ``M^(s) M_s^(i) [0, 0, 1]^T``; that order
    does not put the vacancy at p_hat relative to r_s unless r_s's heading in
    r_i's frame is 0 (see docs/decisions.md and the unit test), so the
    composition is used (a typo in the formula, not a change to the
    algorithm).

    Examples
    --------
    >>> v = Vacancy(1.0, 0.0, 0.0, "A", 0)
    >>> x, y, th = vacancy_in_observer_frame((2.0, 0.0, math.pi / 2), v)
    >>> round(x, 12), round(y, 12), round(th, 12)
    (2.0, 1.0, 1.570796326795)

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-A (the equations after Def. 9).
    """
    ox, oy, oth = float(observed_owner[0]), float(observed_owner[1]), float(observed_owner[2])
    c, s = math.cos(oth), math.sin(oth)
    return (ox + c * vacancy.x - s * vacancy.y, oy + s * vacancy.x + c * vacancy.y,
            wrap_angle(oth + vacancy.theta))


# ---------------------------------------------------------------------------
# Algorithm 1: compute message (001 Sec. V-B)
# ---------------------------------------------------------------------------

def get_parent_msg(eligible: Sequence[Song2016Message], root_id: int | None,
                   relocate_id: int | None, stable_first: bool = True) -> Song2016Message | None:
    """Algorithm 1 line 27: the message of the robot chosen as spanning-tree parent.

    Sec. V-B: "Each robot that has at least one stable neighbor, chooses for
    its parent in this tree the stable neighbor that is the fewest hops from
    the root.  Each robot with no stable neighbors also chooses a parent to
    minimize hops to the root [...].  A special exception [...] is that no
    robot chooses the relocate robot as its parent, if it has another
    neighbor with the same or fewer hops to the root.  Ties, if any, are
    broken in favor of the highest ID."

    Candidates are the eligible messages that carry a path from the same root
    (``root_id``); hops are ``len(path_from_root) - 1``.

    ``stable_first=False`` is the rule as the proof of Lemma 12 states it: "each
    non-root robot selects the neighbor with 1) the shortest path to root, 2) the
    highest ID among neighbors (excluding the relocate robot if the relocate robot is
    one of its neighbors)", with no preference for stable neighbors (see
    :data:`PARENT_RULES` and docs/decisions.md).

    Examples
    --------
    >>> def m(i, path, stable=False):
    ...     return Song2016Message(i, 9, 9, 5, None, None, False, stable, path, (5,))
    >>> get_parent_msg([m(5, (9, 5)), m(3, (9, 2, 3))], 9, 5).sender_id  # 5 is relocate, 3 farther
    5
    >>> get_parent_msg([m(5, (9, 5)), m(3, (9, 3))], 9, 5).sender_id     # same hops: not the relocate robot
    3
    >>> get_parent_msg([m(4, (9, 4)), m(6, (9, 2, 6), stable=True)], 9, 5).sender_id  # stable first
    6

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-B, Algorithm 1 lines 26-30; Lemma 12.
    """
    if root_id is None:
        return None
    cands = [m for m in eligible if m.root_id == root_id and m.path_from_root]
    if not cands:
        return None
    if stable_first:
        stable = [m for m in cands if m.stable]
        if stable:
            cands = stable
    # One pass: the best candidate (fewest hops, then the highest ID; the first on a
    # full tie), the best one that is not the relocate robot, and the relocate
    # robot's hops.  The exception drops the relocate robot when another candidate
    # has the same or fewer hops; the best of the rest is then the best other.
    best = other = None
    best_len = best_id = other_len = other_id = 0
    rel_hops = -1
    for m in cands:
        lm = len(m.path_from_root)
        sid = m.sender_id
        if best is None or lm < best_len or (lm == best_len and sid > best_id):
            best, best_len, best_id = m, lm, sid
        if relocate_id is not None and sid == relocate_id:
            if rel_hops < 0:
                rel_hops = lm
        elif other is None or lm < other_len or (lm == other_len and sid > other_id):
            other, other_len, other_id = m, lm, sid
    if rel_hops >= 0 and other is not None and other_len <= rel_hops:
        return other
    return best


def _read_inbox(my_id: int, root: int | None, relocate: int | None,
                in_messages: Sequence[Song2016Message], per_message: bool) -> tuple:
    """001 Alg. 1 lines 8-22: what this robot takes from inMessages.

    The two readings of line 12 (:data:`RUMOR_FILTERS`) differ only there: as
    printed (``per_message``), a message whose pathFromRoot *or*
    pathFromRelocate holds myID is not eligible; read per field (Sec. V-B's
    prose), root information (lines 14-16) needs myID not in pathFromRoot and
    relocate information (line 18) myID not in pathFromRelocate.  Lines 13 and
    21-22 are folded into the one pass: rootID and relocateID only grow, and no
    message accepted before the one that raises an ID carries the larger ID, so
    the candidates and the shortest path restart there and are then kept (ties:
    the highest sender, the first one on equal IDs), exactly as the shortest
    path over the eligible messages that carry the final ID.

    Returns
    -------
    tuple
        ``(highestID, rootID, relocateID, vacancyFromMsgs, root_cands,
        minRootPath, minRelocatePath)``; ``root_cands`` are the accepted
        messages that carry rootID, in order (getParentMsg's candidates, line 27).
    """
    # 3 myMsg.highestID <- myID;  8 eligibleMsgs <- {} (kept as the messages that carry the
    #   current rootID, root_cands, and the shortest paths so far);  9 vacancyFromMsgs <- null
    highest = my_id
    root_cands: list[Song2016Message] = []
    root_path = reloc_path = None
    root_len = root_sender = reloc_len = reloc_sender = 0
    vacancy_from_msgs: Vacancy | None = None
    # 10 foreach inMsg in inMessages do
    for m in in_messages:
        # 11 myMsg.highestID <- max(myMsg.highestID, inMsg.highestID)
        h = m.highest_id
        if h > highest:
            highest = h
        # 12 if not inMsg.pathFromRoot.contains(myID) and not
        #       inMsg.pathFromRelocate.contains(myID) then
        in_root_path = my_id in m.path_from_root
        in_reloc_path = my_id in m.path_from_relocate
        if per_message:
            in_root_path = in_reloc_path = in_root_path or in_reloc_path
        # 13-17 (with 21): rootID and vacancyFromMsgs, the eligible messages that carry
        #    rootID and the shortest pathFromRoot among them (None is -inf, lines 6-7)
        if not in_root_path:
            r = m.root_id
            if r is not None:
                if root is None or r > root:
                    root = r
                    vacancy_from_msgs = m.vacancy
                    root_cands = [m]
                    root_path = m.path_from_root
                    root_len, root_sender = len(root_path), m.sender_id
                elif r == root:
                    root_cands.append(m)
                    p = m.path_from_root
                    lp = len(p)
                    if (root_path is None or lp < root_len
                            or (lp == root_len and m.sender_id > root_sender)):
                        root_path, root_len, root_sender = p, lp, m.sender_id
        # 18 (with 22): relocateID <- max(relocateID, inMsg.relocateID), and the
        #    shortest pathFromRelocate among the eligible messages that carry it
        if not in_reloc_path:
            r = m.relocate_id
            if r is not None:
                if relocate is None or r > relocate:
                    relocate = r
                    reloc_path = m.path_from_relocate
                    reloc_len, reloc_sender = len(reloc_path), m.sender_id
                elif r == relocate:
                    p = m.path_from_relocate
                    lp = len(p)
                    if (reloc_path is None or lp < reloc_len
                            or (lp == reloc_len and m.sender_id > reloc_sender)):
                        reloc_path, reloc_len, reloc_sender = p, lp, m.sender_id
        # 19 end
    # 20 end;  21 minRootPath, 22 minRelocatePath (none: the empty list)
    min_root_path = () if root_path is None else root_path
    min_reloc_path = () if reloc_path is None else reloc_path
    return highest, root, relocate, vacancy_from_msgs, root_cands, min_root_path, min_reloc_path


def _parent_and_subtree(my_id: int, stable: bool, root: int | None, relocate: int | None,
                        root_cands: list[Song2016Message], parent_rule: str
                        ) -> tuple[Song2016Message | None, int | None, bool]:
    """001 Alg. 1 lines 26-30: the spanning-tree parent and the subtree marker.

    Returns
    -------
    (parentMsg or None, parentID or None, subtree)
        ``(None, None, False)`` for the root (line 26).
    """
    # 26 if myID != myMsg.rootID then
    if my_id == root:
        return None, None, False
    # 27 parentMsg <- getParentMsg(eligibleMsgs, myMsg.pathFromRoot)
    #    (root_cands: the eligible messages that carry this rootID, the only
    #    candidates getParentMsg considers)
    #    (parent_rule "relocate_route": the relocate robot -- myID = relocateID
    #    and unstable, as line 29 reads it -- follows its path to the root,
    #    Lemma 12's rule; everyone else Sec. V-B's stable-first rule)
    stable_first = (parent_rule == "stable_first"
                    or (parent_rule == "relocate_route"
                        and (stable or my_id != relocate)))
    parent_msg = get_parent_msg(root_cands, root, relocate, stable_first)
    # 28 myMsg.parentID <- parentMsg.senderID
    parent_id = None if parent_msg is None else parent_msg.sender_id
    # 29 myMsg.subtree <- myID = myMsg.relocateID or parentMsg.subtree
    subtree = (my_id == relocate) or (parent_msg is not None and parent_msg.subtree)
    # 30 end
    return parent_msg, parent_id, subtree


def compute_message(my_id: int, stable: bool, my_vacancy: Vacancy | None,
                    in_messages: Sequence[Song2016Message], rumor_filter: str = "message",
                    parent_rule: str = "relocate_route"
                    ) -> tuple[Song2016Message, Song2016Message | None]:
    """Algorithm 1 of 001 ("Compute message"), line by line.

    Lines 1-7 (this robot's own values), 23-25 (vacancy and paths) and 31 are
    here; lines 8-22 (what the inbox says) are :func:`_read_inbox`, lines 26-30
    (parent and subtree) :func:`_parent_and_subtree`.

    Parameters
    ----------
    my_id : int
        myID.
    stable : bool
        Whether this robot is stable (line 4).
    my_vacancy : Vacancy or None
        getVacancy() (line 5): this robot's most important vacancy, or None.
    in_messages : sequence of Song2016Message
        inMessages, iterated in this order (the controller passes them in
        increasing sender ID).
    rumor_filter : {"message", "field"}
        How line 12 rejects information (see :data:`RUMOR_FILTERS`).
    parent_rule : {"relocate_route", "stable_first", "fewest_hops"}
        Which statement of the parent rule line 27 follows (:data:`PARENT_RULES`).

    Returns
    -------
    (Song2016Message, Song2016Message or None)
        myMsg, and parentMsg of line 27 (None for the root or when no
        candidate exists).

    Examples
    --------
    A robot that hears the root (9) and an unstable robot (7):

    >>> root = Song2016Message(9, 9, 9, None, None, Vacancy(1, 0, 0, "A", 0), False, True, (9,), (9,))
    >>> r7 = Song2016Message(7, 9, 9, 7, 9, Vacancy(1, 0, 0, "A", 0), True, False, (9, 7), (7,))
    >>> msg, parent = compute_message(5, False, None, [r7, root])
    >>> msg.root_id, msg.relocate_id, msg.parent_id, msg.path_from_root, msg.path_from_relocate
    (9, 7, 9, (9, 5), (7, 5))

    The rumor rule (line 12): information that went through me is rejected.

    >>> stale = Song2016Message(4, 9, 8, None, 5, None, False, True, (8, 5, 4), (4,))
    >>> compute_message(5, False, None, [stale])[0].root_id is None
    True

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V-B, Table I, Algorithm 1.
    """
    if rumor_filter not in RUMOR_FILTERS:
        raise UsageError(f"rumor_filter={rumor_filter!r} is not one of {RUMOR_FILTERS!r}")
    # 1 myMsg <- empty message;  2 myMsg.senderID <- myID
    # 3 myMsg.highestID <- myID  (in _read_inbox, with line 11)
    # 4 myMsg.stable <- I am stable ? true : false  (argument `stable`)
    # 5 myVacancy <- getVacancy()  (argument `my_vacancy`)
    # 6 myMsg.rootID <- (myMsg.stable and myVacancy != null) ? myID : -inf
    root = my_id if (stable and my_vacancy is not None) else None
    # 7 myMsg.relocateID <- (not myMsg.stable) ? myID : -inf
    relocate = my_id if not stable else None
    # 8-22 the inbox: highestID, rootID, relocateID, vacancyFromMsgs, the shortest paths
    highest, root, relocate, vacancy_from_msgs, root_cands, min_root_path, min_reloc_path = _read_inbox(
        my_id, root, relocate, in_messages, rumor_filter == "message")
    # 23 myMsg.vacancy <- (myID = myMsg.rootID) ? myVacancy : vacancyFromMsgs
    vacancy = my_vacancy if my_id == root else vacancy_from_msgs
    # 24 myMsg.pathFromRoot <- minRootPath.append(myID)
    # 25 myMsg.pathFromRelocate <- minRelocatePath.append(myID)
    path_from_root = min_root_path + (my_id,)
    path_from_relocate = min_reloc_path + (my_id,)
    # 26-30 parentMsg, myMsg.parentID, myMsg.subtree
    parent_msg, parent_id, subtree = _parent_and_subtree(my_id, stable, root, relocate, root_cands,
                                                         parent_rule)
    # 31 return myMsg
    msg = Song2016Message(my_id, highest, root, relocate, parent_id, vacancy, subtree, stable,
                          path_from_root, path_from_relocate)
    return msg, parent_msg


# ---------------------------------------------------------------------------
# Configuration and assumptions
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class Song2016Config:
    """The algorithm-specific values, resolved (see :meth:`Song2016.config`).

    Attributes
    ----------
    communication_timeout : int
        Def. 10, in steps (default: the number of robots, 001 Sec. VI).
    movement_timeout : int
        Steps a robot waits, once it is supposed to move, before it moves
        (default: the number of robots, 001 Sec. VI; docs/decisions.md).
    d_s : float
        The safe distance of Sec. V-C (default ``(phi - v*dt)/2``).
    arrival_epsilon : float
        Footnote 2's epsilon: arrival distance at the vacancy.
    heading_epsilon : float
        Arrival tolerance of the orientation (radians).
    vacancy_tolerance : float
        A stable robot this close to p_hat fills the vacancy (Def. 9); default
        half the shortest lattice edge (footnote 2).
    rumor_filter : str
        One of :data:`RUMOR_FILTERS`.
    parent_rule : str
        One of :data:`PARENT_RULES`.
    """

    communication_timeout: int
    movement_timeout: int
    d_s: float
    arrival_epsilon: float
    heading_epsilon: float
    vacancy_tolerance: float
    rumor_filter: str
    parent_rule: str = "relocate_route"


#: A step number no run reaches (repeat_horizon when no timeout is pending).
_NEVER = 2 ** 62

#: The ``Params.extra`` keys 001's algorithm reads (``--param KEY=VALUE``), with their types and ranges;
#: the engine refuses any other key (issue 29).  None as a default: computed, as the meaning says.
PARAMETERS = (
    ParamSpec("communication_timeout", int, None, low=0,
              meaning="Def. 10's timeout in steps; default the number of robots (001 Sec. VI)"),
    ParamSpec("movement_timeout", int, None, low=0,
              meaning="steps a robot waits before it moves; default the number of robots"),
    ParamSpec("d_s", float, None, meaning="Sec. V-C's safe distance; default (phi - v*dt)/2 "
              "(assumption safe_distance_in_range: 0 < d_s < phi - v*dt)"),
    ParamSpec("arrival_epsilon", float, 1e-6, low=0, low_open=True,
              meaning="footnote 2's arrival distance at the vacancy"),
    ParamSpec("heading_epsilon", float, 1e-6, low=0, low_open=True,
              meaning="arrival tolerance of the heading, radians"),
    ParamSpec("vacancy_tolerance", float, None, low=0, low_open=True,
              meaning="a stable robot this close to p_hat fills the vacancy (Def. 9); default half the "
                      "shortest lattice edge"),
    ParamSpec("rumor_filter", str, "field", choices=RUMOR_FILTERS,
              meaning="how rumors of stale roots are dropped (docs/decisions.md)"),
    ParamSpec("parent_rule", str, None, choices=PARENT_RULES,
              meaning="which neighbor a robot takes as parent (Sec. V-B); default the reading's"),
)
_EXTRA_KEYS = tuple(s.name for s in PARAMETERS)
#: keys every algorithm may be given (the checkers read them; engine/parameters.py)
_COMMON_KEYS = ("robot_radius",)


def _check_count(name: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise UsageError(f"{name}={value!r} must be a whole number of steps >= 0",
                         fix=f"set {name} to e.g. the number of robots (001 Sec. VI)")
    return int(value)


def _check_pos(name: str, value: Any) -> float:
    if isinstance(value, bool):
        raise UsageError(f"{name}={value!r} must be a number > 0")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise UsageError(f"{name}={value!r} must be a number > 0") from None
    if not (math.isfinite(x) and x > 0):
        raise UsageError(f"{name}={value!r} must be a finite number > 0")
    return x


# ---------------------------------------------------------------------------
# The sequential fill of 001 Sec. VI (the predicted final formation)
# ---------------------------------------------------------------------------

def sequential_fill(lattice, n: int, tolerance: float | None = None
                    ) -> list[tuple[tuple[float, float, float], str]]:
    """The final formation 001 Sec. VI predicts, from the lattice graph alone.

    "starting from the first stable (the highest ID) robot, the pattern is
    constructed sequentially by filling all of its vacancies first, then
    filling the vacancies of the second stable (the second highest ID)
    robot" (Sec. VI).  Robot k (k = 0 the highest ID) gets the k-th pose in
    the frame of robot 0 (role v0 at the origin); each new robot fills the
    most important vacancy (first out-edge without a robot, Def. 9) of the
    earliest-placed robot that still has one.

    This is the simulator-free prediction used by the acceptance tests; it
    shares no code with the controller except the lattice graph itself.

    Returns
    -------
    list of ((x, y, theta), role)
        In fill order (index = rank of the robot's ID from the highest).

    Examples
    --------
    >>> from swarmproof.models.lattice import LatticeGraph
    >>> from swarmproof.models.se2 import SE2
    >>> sq = LatticeGraph("square", ["A"], [("A", "A", SE2(1, 0, 0)), ("A", "A", SE2(0, 1, 0)),
    ...                                     ("A", "A", SE2(-1, 0, 0)), ("A", "A", SE2(0, -1, 0))])
    >>> [tuple(round(c, 9) for c in p[:2]) for p, _ in sequential_fill(sq, 6)]
    [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (2.0, 0.0)]
    """
    if tolerance is None:
        tolerance = 0.5 * min(e.transform.norm() for e in lattice.edges)
    placed: list[tuple[tuple[float, float, float], str]] = [((0.0, 0.0, 0.0), lattice.v0)]
    tol2 = tolerance * tolerance
    while len(placed) < n:
        done = False
        for (px, py, pth), role in placed:
            c, s = math.cos(pth), math.sin(pth)
            for e in lattice.out_edges(role):
                t = e.transform
                x, y = px + c * t.x - s * t.y, py + s * t.x + c * t.y
                if any((x - q[0][0]) ** 2 + (y - q[0][1]) ** 2 <= tol2 for q in placed):
                    continue
                placed.append(((x, y, wrap_angle(pth + t.theta)), e.target))
                done = True
                break
            if done:
                break
        if not done:
            raise UsageError(f"lattice {lattice.name!r} has no vacancy left after {len(placed)} robots",
                             fix="a finite lattice graph holds fewer robots than requested")
    return placed


# ---------------------------------------------------------------------------
# The controller
# ---------------------------------------------------------------------------

def _refuse_foreign_messages(me: int, keys: list, inbox: list) -> None:
    """Raise :class:`ProtocolError` for the first message of ``inbox`` (from senders
    ``keys``) that is not a :class:`Song2016Message` (001 Table I)."""
    for sid, m in zip(keys, inbox):
        if not isinstance(m, Song2016Message):
            raise ProtocolError(f"robot {me} received message={m!r} from robot {sid}, "
                                "not a Song2016Message")


class Song2016Controller:
    """One robot running 001 Sec. V (stable/unstable, Algorithm 1, NCLB motion).

    Created by :meth:`Song2016.controller`; see the module docstring for the
    :meth:`state` keys.
    """

    __slots__ = ("robot_id", "params", "lattice", "cfg", "_out_edges", "_v0", "_radius",
                 "_safe_radius", "stable", "role", "highest_id", "highest_since",
                 "relocate_id", "relocate_since", "root_id", "mover", "mover_since",
                 "_state", "_last_msg", "memoize", "_last_inbox", "_last_stable",
                 "_vac_key", "_vac", "_children", "_values", "_last_vac_in", "_last_ids",
                 "_last_pose_bytes", "_last_cmd", "_last_relocate", "_last_may_move",
                 "_last_idle")

    def __init__(self, robot_id: int, params: Params, lattice, cfg: Song2016Config,
                 memoize: bool = True) -> None:
        self.robot_id = robot_id
        self.memoize = memoize
        self.params = params
        self.lattice = lattice
        self.cfg = cfg
        self._out_edges = {
            role: tuple((e.transform.x, e.transform.y, e.transform.theta, e.target, e.index)
                        for e in lattice.out_edges(role))
            for role in lattice.roles
        }
        self._v0 = lattice.v0
        self._radius = bounded_range_radius(params.range, params.v, params.dt)
        self._safe_radius = self._radius * (1.0 - SAFE_MARGIN)
        # Sec. V-A: "Each robot begins in the unstable state".
        self.stable = False
        self.role: str | None = None
        # Def. 10 clocks: the value last known and the step it last changed.
        self.highest_id = robot_id
        self.highest_since = 0
        self.relocate_id: int | None = robot_id
        self.relocate_since = 0
        self.root_id: int | None = None
        self.mover: str | None = None
        self.mover_since = 0
        self._last_msg: Song2016Message | None = None
        # Memo of the last step (performance only; the results are identical, see
        # tests): the inbox (message objects), the vacancy inputs, the children.
        self._last_inbox: list = []
        self._last_stable = False
        self._last_vac_in: Vacancy | None = None
        self._vac_key: tuple | None = None
        self._vac: Vacancy | None = None
        self._children: tuple = ()
        self._values: tuple | None = None
        self._last_ids: tuple | None = None
        self._last_pose_bytes: bytes | None = None
        self._last_cmd: Command | None = None
        self._last_idle = False  # the last command was built without a goal (0.0, 0.0)
        self._last_relocate = False
        self._last_may_move = False
        self._state: tuple = self._snapshot(None, False, (), False, False, None, None, None)

    # -- helpers -------------------------------------------------------------
    def _my_vacancy(self, pose_of: Mapping[int, Sequence[float]],
                    messages: Iterable[tuple[int, Any]]) -> Vacancy | None:
        """getVacancy() (Algorithm 1 line 5): the most important vacancy (Def. 9).

        ``messages`` are ``(sender, message)`` pairs; a neighbor is stable when
        its last message said so (Table I "stable")."""
        if not self.stable:
            return None
        stable_xy = tuple((pose_of[i][0], pose_of[i][1]) for i, m in messages
                          if m.stable and i in pose_of)
        key = (self.role, stable_xy)
        if self.memoize and key == self._vac_key:
            return self._vac
        vac = vacancies(self._out_edges[self.role], stable_xy, self.cfg.vacancy_tolerance)
        self._vac_key = key
        self._vac = vac[0] if vac else None
        return self._vac

    def _message(self, my_vac: Vacancy | None, inbox: list, same_inbox: bool) -> Song2016Message:
        """Algorithm 1, or the last message when none of its inputs (my stable
        flag, my vacancy, the inbox) changed (performance only)."""
        last = self._last_msg
        if (self.memoize and same_inbox and last is not None and self.stable == self._last_stable
                and my_vac == self._last_vac_in):
            return last
        msg, _ = compute_message(self.robot_id, self.stable, my_vac, inbox, self.cfg.rumor_filter,
                                 self.cfg.parent_rule)
        self._last_stable = self.stable
        self._last_vac_in = my_vac
        if self.memoize and last is not None and msg == last:
            return last  # keep the object: receivers then see an unchanged inbox
        return msg

    def _snapshot(self, parent, relocate, children, subtree, moving, goal, target, vacancy) -> tuple:
        return (
            ("stable", self.stable), ("role", self.role), ("parent", parent),
            ("children", children), ("relocate", relocate), ("subtree", subtree),
            ("moving", moving), ("goal", goal), ("target", target),
            ("safe_radius", self._safe_radius),
            ("highest_id", self.highest_id), ("highest_since", self.highest_since),
            ("root_id", self.root_id),
            ("relocate_id", self.relocate_id), ("relocate_since", self.relocate_since),
            ("mover", self.mover), ("mover_since", self.mover_since),
            ("vacancy", None if vacancy is None else vacancy.as_tuple()),
        )

    # -- protocol ------------------------------------------------------------
    def state(self) -> Hashable:
        """The snapshot described in the module docstring (after the last step)."""
        return self._state

    def step(self, obs: Observation) -> Command:
        """One synchronous step: Algorithm 1, the state changes, NCLB motion.

        In the order of 001 Sec. V: the inbox in increasing sender ID (an
        observation equal to the last one, with no timeout due, repeats the last
        command); Algorithm 1 on the state at the start of the step
        (:meth:`_message`); the timeouts and the roles they give (Def. 10, Sec. V-B:
        :meth:`_take_roles`); the goal of Sec. V-C, where the relocate robot may
        instead arrive and turn stable (:meth:`_goal`); Algorithm 1 again after
        turning stable (:meth:`_rebroadcast`); NCLB motion within the children's
        bounded ranges (:meth:`_nclb_motion`); the state snapshot
        (:meth:`_record_state`) and the command (:meth:`_command`).
        """
        t = obs.step
        me = self.robot_id
        ids = obs.neighbor_ids or ()
        obs_msgs = obs.messages
        keys = sorted(obs_msgs)
        inbox = list(map(obs_msgs.__getitem__, keys))  # Algorithm 1 line 10: increasing sender ID
        # unchanged inbox: the same message objects (or equal ones: same content)
        same_inbox = inbox == self._last_inbox
        if not same_inbox:
            if not all([type(m) is Song2016Message for m in inbox]):
                _refuse_foreign_messages(me, keys, inbox)
            self._last_inbox = inbox
        pose_bytes = obs.neighbor_poses.tobytes()
        if self.memoize:
            if (same_inbox and ids == self._last_ids and pose_bytes == self._last_pose_bytes
                    and self._last_cmd is not None and not self._time_matters(t)):
                # Every input is what it was last step and no timeout expires now: the
                # decision is the same (performance only; the trace is identical).
                return self._last_cmd
            self._last_ids = ids
            self._last_pose_bytes = pose_bytes
        # ID -> body-frame pose of the sensed neighbors, built only when a pose is read
        # (a vacancy, a goal, the safe region); membership alone is read from `ids`.
        pose_of = dict(zip(ids, obs.neighbor_poses.tolist())) if self.stable else None

        # Algorithm 1 (lines 1-31) with this robot's state at the start of the step.
        my_vac = self._my_vacancy(pose_of, zip(keys, inbox)) if self.stable else None
        msg = self._message(my_vac, inbox, same_inbox)
        # Def. 10, Sec. V-A to V-C: the timeouts; stable, relocate robot, moving subtree.
        relocate, mover, may_move, changed = self._take_roles(msg, t)
        parent = msg.parent_id
        goal = heading = None
        if may_move and parent is not None and parent in ids:
            if pose_of is None:
                pose_of = dict(zip(ids, obs.neighbor_poses.tolist()))
            goal, heading, arrived = self._goal(mover, parent, msg, pose_of, obs_msgs)
            changed = changed or arrived
        if changed:
            # The broadcast reflects the state after this step's change.
            relocate = False
            goal = None
            if pose_of is None:
                pose_of = dict(zip(ids, obs.neighbor_poses.tolist()))
            msg, my_vac = self._rebroadcast(t, pose_of, keys, inbox, same_inbox)
            parent = msg.parent_id

        # NCLB (Sec. V-C): the children are the robots whose last message named me
        # as parent; the safe region is the intersection of their bounded ranges.
        children = tuple([sid for sid, m in zip(keys, inbox) if m.parent_id == me and sid in ids])
        turn = forward = 0.0
        target = None
        if goal is not None:
            turn, forward, target = self._nclb_motion(goal, heading, mover, children, pose_of,
                                                      obs_msgs)
        self._record_state(msg, parent, children, relocate, forward > 0.0, goal, target, my_vac)
        self._last_relocate = relocate
        self._last_may_move = may_move and not changed
        return self._command(msg, goal, turn, forward)

    # -- the steps of step() ------------------------------------------------------
    def _take_roles(self, msg: Song2016Message, t: int) -> tuple[bool, str | None, bool, bool]:
        """The timeouts and the roles they give, from this step's message.

        001 Def. 10 and Sec. V-B (the communication timeout on highestID and on
        relocateID), Sec. V-A (the highest-ID robot turns stable, role v0),
        Sec. V-C and Sec. VI (the moving subtree and its movement timeout).

        Returns
        -------
        (relocate, mover, may_move, changed)
            Whether this robot is the confirmed relocate robot; ``"relocate"``,
            ``"subtree"`` or None; whether its movement timeout has passed; whether
            it turned stable this step.
        """
        me = self.robot_id
        cfg = self.cfg
        # Def. 10 / Sec. V-B: the timeouts count from the last change of the
        # principal information.
        if msg.highest_id != self.highest_id:
            self.highest_id = msg.highest_id
            self.highest_since = t
        if msg.relocate_id != self.relocate_id:
            self.relocate_id = msg.relocate_id
            self.relocate_since = t
        self.root_id = msg.root_id
        changed = False
        # Sec. V-A/V-B: the robot that has the highest ID becomes stable (role v0)
        # once the communication timeout has passed since its highest ID last changed.
        if (not self.stable and msg.highest_id == me
                and t - self.highest_since >= cfg.communication_timeout):
            self.stable = True
            self.role = self._v0
            changed = True
        # Sec. V-B: the highest-ID unstable robot becomes the relocate robot after
        # the same timeout on relocateID.
        relocate = (not self.stable and msg.relocate_id == me
                    and t - self.relocate_since >= cfg.communication_timeout)
        # Sec. V-C: only the relocate robot and its descendants (the moving subtree,
        # Table I "subtree") move; the movement timeout (Sec. VI) runs from when
        # the robot became one of them.
        if relocate:
            mover = "relocate"
        elif not self.stable and msg.subtree and msg.relocate_id != me:
            mover = "subtree"
        else:
            mover = None
        if mover != self.mover:
            self.mover = mover
            self.mover_since = t
        may_move = mover is not None and t - self.mover_since >= cfg.movement_timeout
        return relocate, mover, may_move, changed

    def _goal(self, mover: str, parent: int, msg: Song2016Message,
              pose_of: Mapping[int, Sequence[float]], messages: Mapping[int, Any]
              ) -> tuple[tuple[float, float] | None, float | None, bool]:
        """Where a robot that may move heads this step (001 Sec. V-C cases 2 and 3).

        The relocate robot at the vacancy turns stable instead (Sec. V-A,
        footnote 2).

        Returns
        -------
        (goal, heading, arrived)
            The body-frame goal ``(x, y)`` or None; the vacancy's heading when the
            goal is the vacancy, else None; whether this robot turned stable.
        """
        cfg = self.cfg
        px, py, _ = pose_of[parent]
        if mover == "relocate":
            # Sec. V-C case 2: toward the parent, or toward the vacancy when the
            # parent is the root.
            if parent == msg.root_id:
                root_msg = messages.get(parent)
                vac = None if root_msg is None else root_msg.vacancy
                if vac is None:
                    return None, None, False
                vx, vy, vth = vacancy_in_observer_frame(pose_of[parent], vac)
                if (math.hypot(vx, vy) <= cfg.arrival_epsilon
                        and abs(wrap_angle(vth)) <= cfg.heading_epsilon):
                    # Sec. V-A: "Robot ri will change its state from unstable to
                    # stable after it reaches this pose" (footnote 2: within eps).
                    self.stable = True
                    self.role = vac.role
                    return None, None, True
                return (vx, vy), vth, False
            return (px, py), None, False
        # Sec. V-C case 3: toward the parent only when farther than d_s.
        if math.hypot(px, py) > cfg.d_s:
            return (px, py), None, False
        return None, None, False

    def _rebroadcast(self, t: int, pose_of: Mapping[int, Sequence[float]], keys: list,
                     inbox: list, same_inbox: bool) -> tuple[Song2016Message, Vacancy | None]:
        """Algorithm 1 again for a robot that turned stable this step (001 Sec. V-A).

        It stops moving; its message carries its vacancy (Def. 9) and the rootID
        and relocateID a stable robot computes.  Returns ``(myMsg, its vacancy)``.
        """
        self.mover = None
        self.mover_since = t
        my_vac = self._my_vacancy(pose_of, zip(keys, inbox))
        msg = self._message(my_vac, inbox, same_inbox)
        self.root_id = msg.root_id
        if msg.relocate_id != self.relocate_id:
            self.relocate_id = msg.relocate_id
            self.relocate_since = t
        return msg, my_vac

    def _nclb_motion(self, goal: tuple[float, float], heading: float | None, mover: str,
                     children: tuple, pose_of: Mapping[int, Sequence[float]],
                     messages: Mapping[int, Any]) -> tuple[float, float, tuple | None]:
        """The motion toward ``goal`` that No Child Left Behind allows (001 Sec. V-C).

        Returns
        -------
        (turn, forward, target)
            ``target``: where the step ends, in the body frame; None when the
            robot neither turns nor moves.
        """
        cfg = self.cfg
        centers = [(pose_of[c][0], pose_of[c][1]) for c in children]
        if math.hypot(goal[0], goal[1]) <= cfg.arrival_epsilon:
            # At the vacancy: turn to its orientation (Sec. V-A), no translation.
            turn = 0.0 if heading is None else float(heading)
            return turn, 0.0, (0.0, 0.0)
        if mover == "relocate" and any(
                not messages[c].stable and math.hypot(pose_of[c][0], pose_of[c][1]) > cfg.d_s
                for c in children):
            # Fig. 11 [left] and Sec. V-C: "the relocate robot first waits for its
            # child to come closer" (dist(r_p, r_c) > d_s: r_p waits).  Only for
            # children that will come closer: a stable child never moves (Sec. V-C
            # case 1), so it is not waited for (it still bounds the safe region).
            return 0.0, 0.0, None
        return self._safe_step(goal, mover, centers)

    def _safe_step(self, goal: tuple[float, float], mover: str,
                   centers: list) -> tuple[float, float, tuple | None]:
        """One step toward ``goal`` that ends in the safe region (001 Def. 8, Sec. V-C).

        The safe region is the intersection of the children's bounded ranges
        (``centers``); an empty one, or a step that would end outside it, means
        "the robot does not move".  Returns ``(turn, forward, target)`` as
        :meth:`_nclb_motion`.
        """
        if mover == "subtree":
            # Sec. V-C case 3: "moves directly toward its parent while staying
            # within its own NCLB safe region" -- along the line to the parent.
            way = farthest_point_toward(goal, centers, self._safe_radius)
        else:
            # the relocate robot: the intermediate goal of Figs. 9 and 11
            way = closest_point_in_discs(goal, centers, self._safe_radius)
        if way is not None and (way[0] != 0.0 or way[1] != 0.0):
            tr, fw, ex, ey = reachable_point(way, self.params.v, self.params.omega,
                                             self.params.dt)
            if fw > 0.0 and not in_discs(ex, ey, centers, self._safe_radius):
                # The end of the step would leave the safe region (possible only
                # when the robot starts outside it): do not move.
                tr = fw = 0.0
            if fw > 0.0 or tr != 0.0:
                return tr, fw, ((ex, ey) if fw > 0.0 else (0.0, 0.0))
        # way is None: empty safe region -> "the robot does not move".
        return 0.0, 0.0, None

    def _record_state(self, msg: Song2016Message, parent, children: tuple, relocate: bool,
                      moving: bool, goal, target, my_vac: Vacancy | None) -> None:
        """Keep this step's message and state snapshot (module docstring); the
        snapshot object stays when no value changed (performance only)."""
        self._last_msg = msg
        values = (self.stable, self.role, parent, children, relocate, msg.subtree, moving,
                  goal, target, self.highest_id, self.highest_since, self.root_id,
                  self.relocate_id, self.relocate_since, self.mover, self.mover_since, my_vac)
        if not (self.memoize and values == self._values):
            self._values = values
            self._state = self._snapshot(parent, relocate, children, msg.subtree, moving,
                                         goal, target, my_vac)

    def _command(self, msg: Song2016Message, goal, turn: float, forward: float) -> Command:
        """The command: broadcast ``msg``, turn, then drive.  With no goal and the
        same message object as the last idle step, the last command object."""
        last = self._last_cmd
        if goal is None:
            if self._last_idle and last.message is msg and self.memoize:
                # no goal (turn = forward = 0.0) again, same message: the last command
                return last
            self._last_idle = True
        else:
            self._last_idle = False
        cmd = Command(message=msg, turn=turn, forward=forward)
        self._last_cmd = cmd
        return cmd

    def repeat_step(self, t: int) -> Command | None:
        """The command of :meth:`step` for an observation equal to the last one but for
        the step number ``t``, or None when :meth:`step` must be called.

        The engine calls it instead of :meth:`step` when this robot senses the same
        neighbor IDs at bit-identical body-frame poses and hears the very same message
        objects as in the previous step (performance only).  It is the first test
        :meth:`step` itself makes: with every input unchanged, only an expiring
        timeout can change the decision, so the last command is repeated and nothing
        else happens (the state snapshot stays the same object).
        """
        if self.memoize and self._last_cmd is not None and not self._time_matters(t):
            return self._last_cmd
        return None

    def repeat_horizon(self, t: int) -> int:
        """The first step after ``t`` at which a timeout of this robot can expire.

        Called by the engine after this robot's :meth:`step` or :meth:`repeat_step`
        at step ``t``: for every step ``s`` with ``t < s <`` the result,
        :meth:`_time_matters` is False, so with an unchanged observation
        :meth:`repeat_step` would return the same command (the engine does not ask).
        Each condition of :meth:`_time_matters` is a threshold in the step number
        given the last message and clocks: the communication timeout on highestID
        and on relocateID (Def. 10) and the movement timeout (Sec. VI).

        Examples
        --------
        >>> from swarmproof.models.library import load
        >>> c = Song2016(n_robots=5).controller(3, Params(range=1.2, v=0.05), load("square"), None)
        >>> cmd = c.step(Observation(0, 3, (), np.zeros((0, 3)), {}))
        >>> c.repeat_horizon(0)   # alone, robot 3 becomes stable after the timeout of 5
        5
        """
        if not self.memoize or self._last_cmd is None:
            return t + 1
        cfg = self.cfg
        msg = self._last_msg
        me = self.robot_id
        h = math.inf
        if not self.stable:
            if msg.highest_id == me:
                h = min(h, self.highest_since + cfg.communication_timeout)
            if msg.relocate_id == me:
                if not self._last_relocate:
                    h = min(h, self.relocate_since + cfg.communication_timeout)
            elif self._last_relocate:
                h = t + 1
        if self.mover is not None and not self._last_may_move:
            h = min(h, self.mover_since + cfg.movement_timeout)
        return t + 1 if h <= t else (h if h != math.inf else _NEVER)

    def _time_matters(self, t: int) -> bool:
        """Whether a timeout of this robot expires at step ``t`` given last step's
        message (the only inputs of :meth:`step` that depend on time alone)."""
        cfg = self.cfg
        msg = self._last_msg
        if not self.stable:
            if msg.highest_id == self.robot_id and t - self.highest_since >= cfg.communication_timeout:
                return True
            relocate = (msg.relocate_id == self.robot_id
                        and t - self.relocate_since >= cfg.communication_timeout)
            if relocate != self._last_relocate:
                return True
        if self.mover is not None:
            if (t - self.mover_since >= cfg.movement_timeout) != self._last_may_move:
                return True
        return False


# ---------------------------------------------------------------------------
# The algorithm
# ---------------------------------------------------------------------------

class Song2016:
    """The Song & O'Kane 2016 algorithm (001 Sec. V), for the engine.

    Parameters
    ----------
    n_robots : int, optional
        The number of robots; the default of both timeouts (001 Sec. VI: "we
        set both of the communication timeout and the movement timeout as the
        same as the number of robots").  Robots do not know it; it only sets
        the timeouts.  Without it, ``params.extra`` (or the keyword
        arguments) must give both timeouts.
    communication_timeout, movement_timeout, d_s, arrival_epsilon,
    heading_epsilon, vacancy_tolerance, rumor_filter, parent_rule : optional
        Defaults for the values of the same names; ``params.extra`` overrides
        them.  See :class:`Song2016Config`.
    memoize : bool
        Reuse the last step's message, vacancy and state snapshot when their
        inputs are unchanged (performance only: traces are identical either
        way, which the tests check).

    Examples
    --------
    >>> alg = Song2016(n_robots=4)
    >>> p = Params(range=1.2, v=0.05)
    >>> cfg = alg.config(p, 0.5)
    >>> cfg.communication_timeout, cfg.movement_timeout, cfg.d_s
    (4, 4, 0.575)
    >>> [a.name for a in alg.assumptions]
    ['v_dt_below_range', 'safe_distance_in_range', 'communication_timeout_sufficient', 'connected_start']

    References
    ----------
    001_7a4e517b856331bc.txt, Sec. V and VI.
    """

    name = "song2016"
    #: The controller-state fields the shared checkers may read (swarmproof.invariants.capabilities):
    #: ``parent`` (its spanning tree, Sec. V-A) and ``role``.
    state_fields = ("role", "parent")
    #: The seed paper (docs/references.md) whose claims ``claims`` cites.
    paper = "001"
    #: The reading version (protocol.Algorithm.reading: bumped when its behaviour changes on
    #: purpose; CHANGELOG.md); song2016-literal inherits it.
    reading = "1"
    model = RobotModel(sensing="local", communication="neighbors", motion="differential",
                       clocks="sync")
    #: What 001 claims, property -> citation (every checked property is claimed).
    claims = {
        "termination": "001 Thm. 13 (all robots static in finite time)",
        "formation": "001 Thm. 13 (final configuration satisfies the lattice, Def. 2)",
        "connectivity": "001 Lemma 11 (communication graph stays connected)",
        "tree_links": "001 Lemma 11, Sec. V-C (NCLB keeps every spanning-tree link)",
    }
    #: The lemma premises 001's proof uses (docs/proofs.md), each monitored from its lemma's
    #: definition: Lemma 7's step bound, NCLB of Sec. V-C, the relocate case of Lemma 11, a child
    #: moving toward a still parent.
    premise_monitors = ("step_bounded", "nclb", "relocate", "child_toward_parent")
    #: Its own properties (:mod:`.properties`): every link of the decided tree in a case of Lemma
    #: 11's argument, by the algorithm's own reasons (issue 19; a property since issue 32: no lemma
    #: states the case coverage).
    properties = ("tree_link_cases",)
    #: ``swarmproof prove``'s lemmas about it (001's: Lemma 7, NCLB, one link of Lemma 11's
    #: proof, the relocate robot's path, the safe region; ``swarmproof prove --algorithm song2016``).
    lemmas = ("bounded_range", "bounded_range_strict", "nclb_link_kept", "spanning_tree_kept",
              "relocate_stays_in_range", "safe_region_nonempty")
    #: ``swarmproof verify``: the periodic lattices of 000 Figs. 2, 3, 7, 10 robots, 3 starts; and
    #: square n = 20 from seed 1, where a link chosen in the step breaks (Lemma 11's one-step lag).
    verify = VerifyPlan(targets=("square", "hexagon", "octagon-square"), robots=10, seeds=(0, 1, 2), rank=0,
                        more=(("square", 20, (1,)),), explore_cost=152)
    #: The algorithm's own end (Sec. V-C, last paragraph: "the algorithm terminates upon
    #: discovering that no unstable robots remain"); a run that goes static short of it is a
    #: deadlock, and termination is judged violated (:func:`~swarmproof.invariants.termination.judge_termination`).
    own_end = "no unstable robot remains, 001 Sec. V-C"
    #: Its ``Params.extra`` keys (:data:`PARAMETERS`) and the kind of target it forms (a lattice graph).
    parameters = PARAMETERS
    target_kinds = ("lattice",)
    #: The statement of the parent rule this class follows by default (:data:`PARENT_RULES`).
    default_parent_rule = "relocate_route"
    #: The controller class :meth:`controller` builds when not :class:`Song2016Controller` (a
    #: reading of the timeouts replaces it: :class:`Song2016SubtreeClock`).  None: the module's
    #: ``Song2016Controller``, looked up when a controller is built, so a copy of this module
    #: with that name replaced (benchmarks/mutants.py's seeded faults) builds the replacement.
    controller_class = None

    def __init__(self, n_robots: int | None = None, *, communication_timeout: int | None = None,
                 movement_timeout: int | None = None, d_s: float | None = None,
                 arrival_epsilon: float = 1e-6, heading_epsilon: float = 1e-6,
                 vacancy_tolerance: float | None = None, rumor_filter: str = "field",
                 parent_rule: str | None = None, memoize: bool = True) -> None:
        self.memoize = bool(memoize)
        if parent_rule is None:
            parent_rule = self.default_parent_rule
        if n_robots is not None:
            n_robots = _check_count("n_robots", n_robots)
        self.n_robots = n_robots
        self._defaults = {
            "communication_timeout": communication_timeout, "movement_timeout": movement_timeout,
            "d_s": d_s, "arrival_epsilon": arrival_epsilon, "heading_epsilon": heading_epsilon,
            "vacancy_tolerance": vacancy_tolerance, "rumor_filter": rumor_filter,
            "parent_rule": parent_rule,
        }
        self.assumptions = self._make_assumptions()

    def __repr__(self) -> str:
        given = {k: v for k, v in self._defaults.items() if v is not None}
        return f"{type(self).__name__}(n_robots={self.n_robots!r}, {given!r})"

    # -- configuration ---------------------------------------------------
    def _value(self, params: Params, key: str):
        extra = params.extra or {}
        if key in extra:
            return extra[key], f"params.extra[{key!r}]"
        return self._defaults[key], key

    def config(self, params: Params, min_edge: float, n: int | None = None) -> Song2016Config:
        """Resolve the algorithm's values: ``params.extra`` > constructor > default.

        Parameters
        ----------
        params : Params
        min_edge : float
            The shortest lattice edge (for the default vacancy tolerance).
        n : int, optional
            The number of robots, if known here (else ``n_robots``).

        Raises
        ------
        UsageError
            A value of the wrong type or range, naming it, or no way to set a
            timeout (neither ``n_robots`` nor an explicit timeout).
        """
        unknown = sorted(set(params.extra or {}) - set(_EXTRA_KEYS) - set(_COMMON_KEYS))
        if unknown:
            raise UsageError(f"params.extra has unknown key(s) {unknown!r} for song2016",
                             fix=f"use only {list(_EXTRA_KEYS)!r}")
        n_eff = self.n_robots if self.n_robots is not None else n
        vals: dict[str, Any] = {}
        for key in ("communication_timeout", "movement_timeout"):
            value, name = self._value(params, key)
            if value is None:
                if n_eff is None:
                    raise UsageError(f"{key} is unknown: song2016 sets it to the number of robots",
                                     fix="construct Song2016(n_robots=N) or set "
                                         f"params.extra[{key!r}]")
                value = n_eff
            vals[key] = _check_count(name, value)
        value, name = self._value(params, "d_s")
        # any finite d_s is accepted here; the assumption safe_distance_in_range
        # refuses one outside (0, phi - v*dt) unless violations are allowed
        vals["d_s"] = (0.5 * bounded_range_radius(params.range, params.v, params.dt)
                       if value is None else check_finite(name, value))
        for key in ("arrival_epsilon", "heading_epsilon"):
            value, name = self._value(params, key)
            vals[key] = _check_pos(name, value)
        value, name = self._value(params, "vacancy_tolerance")
        vals["vacancy_tolerance"] = 0.5 * min_edge if value is None else _check_pos(name, value)
        value, name = self._value(params, "rumor_filter")
        if value not in RUMOR_FILTERS:
            raise UsageError(f"{name}={value!r} is not one of {RUMOR_FILTERS!r}",
                             fix="'message' (Algorithm 1 line 12 as printed) or 'field'")
        vals["rumor_filter"] = value
        value, name = self._value(params, "parent_rule")
        if value not in PARENT_RULES:
            raise UsageError(f"{name}={value!r} is not one of {PARENT_RULES!r}",
                             fix="'relocate_route' (default: Sec. V-B, the relocate robot on its "
                                 "path to the root), 'stable_first' (Sec. V-B for every robot) or "
                                 "'fewest_hops' (Lemma 12 proof)")
        vals["parent_rule"] = value
        return Song2016Config(**vals)

    # -- assumptions (checked by the engine) ------------------------------
    def _make_assumptions(self) -> tuple[Assumption, ...]:
        def v_dt(params: Params, n, ids):
            if not params.v * params.dt < params.range:
                return (f"v*dt={params.v * params.dt!r} must be < phi=range={params.range!r}")
            return None

        def d_s(params: Params, n, ids):
            r = bounded_range_radius(params.range, params.v, params.dt)
            value, name = self._value(params, "d_s")
            if value is None:
                return None if r > 0 else f"phi - v*dt={r!r} must be > 0 for any d_s"
            try:
                x = float(value)
            except (TypeError, ValueError):
                return f"{name}={value!r} is not a number"
            if not 0 < x < r:
                return f"{name}={value!r} must lie in (0, phi - v*dt) = (0, {r!r})"
            return None

        def timeout(params, n, ids):
            value, name = self._value(params, "communication_timeout")
            if value is None:
                value = self.n_robots if self.n_robots is not None else n
                name = "communication_timeout (default: n_robots)"
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                return f"{name}={value!r} is not a whole number of steps"
            if value < n - 1:
                return (f"{name}={value!r} < n - 1 = {n - 1}: information may need n - 1 "
                        "steps to cross the network")
            return None

        return (
            Assumption("v_dt_below_range", "v*dt < phi", "001 Lemma 7, Def. 8", v_dt),
            Assumption("safe_distance_in_range", "0 < d_s < phi - v*dt", "001 Sec. V-C", d_s),
            Assumption("communication_timeout_sufficient",
                       "communication_timeout >= n - 1 (long enough for information to cross "
                       "the network)", "001 Def. 10, Lemma 12 (O(m) steps for m hops)", timeout),
            # The engine checks it on the initial poses (protocol.connected_start).
            connected_start("001 Lemma 11, Theorem 13, Sec. VI (random but connected starts)"),
        )

    # -- protocol --------------------------------------------------------
    def controller(self, robot_id: int, params: Params, lattice, rng: np.random.Generator
                   ) -> Song2016Controller:
        """A fresh controller (``rng`` is unused: the algorithm is deterministic)."""
        if isinstance(robot_id, bool) or not isinstance(robot_id, (int, np.integer)):
            raise UsageError(f"robot_id={robot_id!r} must be an int (comparable IDs, 001 Sec. III-A)")
        min_edge = min((e.transform.norm() for e in lattice.edges), default=0.0)
        if not min_edge > 0:
            raise UsageError(f"lattice {lattice.name!r} has no edge of positive length",
                             fix="give a lattice graph with edges (001 Def. 1)")
        cfg = self.config(params, min_edge)
        cls = self.controller_class or Song2016Controller
        return cls(int(robot_id), params, lattice, cfg, memoize=self.memoize)

    def default_max_steps(self, params: Params, n: int) -> int:
        """The engine's step cap: twice the Theorem 13 bound, with our constants.

        001 Theorem 13: ``T = sum_{i=1}^{n-1} T_i + O(n)`` with
        ``T_i <= T_timeout + (n-1)(phi/v + 2 pi/omega)``.  Per relocation we
        count the communication timeout twice (stale information must die out
        before the new relocate robot's timeout runs, Sec. V-B) plus the
        movement timeout (Sec. VI), convert times to steps with ``ceil``, and
        double the sum.  A run that hits the cap is inconclusive, not a pass.

        >>> Song2016(n_robots=3).default_max_steps(Params(range=1.2, v=0.05), 3)
        398
        """
        min_edge = 1.0
        try:
            cfg = self.config(params, min_edge, n)
            tc, tm = cfg.communication_timeout, cfg.movement_timeout
        except UsageError:
            tc = tm = int(n)
        v = max(params.v, 1e-9)
        hop = math.ceil((params.range / v + 2 * math.pi / params.omega) / params.dt)
        n1 = max(int(n) - 1, 0)
        return int(2 * (n1 * (2 * tc + tm + n1 * hop) + tc) + 100)

    def finished(self, states: Sequence[Hashable]) -> bool:
        """True when no unstable robot remains (001 Sec. V-C, last paragraph)."""
        for s in states:
            # the snapshot starts with ("stable", flag); anything else is read as a dict
            first = s[0] if type(s) is tuple and s else None
            if type(first) is tuple and len(first) == 2 and first[0] == "stable":
                if not first[1]:
                    return False
            elif not dict(s)["stable"]:
                return False
        return True


class Song2016Literal(Song2016):
    """Song & O'Kane 2016 with the parent rule of Sec. V-B read literally for every robot,
    the relocate robot included (``parent_rule="stable_first"``): "chooses for its parent
    [...] the stable neighbor that is the fewest hops from the root".

    Everything else is :class:`Song2016`.  It is the other reading of the paper's two
    statements of the rule (docs/decisions.md, "Relocate robot's parent"), reported beside
    the default: on the acceptance starts it deadlocks on 28 of 240 (hexagon n = 40 on 16
    of 20; docs/song2016.md), the relocate robot parked on a stable parent that is no closer
    to the root -- Theorem 13 does not hold for this reading.  ``swarmproof verify`` runs
    it where the deadlock appears.

    >>> Song2016Literal(n_robots=4).config(Params(range=1.2, v=0.05), 0.5).parent_rule
    'stable_first'
    """

    name = "song2016-literal"
    default_parent_rule = "stable_first"
    #: verify: hexagon n = 40 from seed 2, one of the 16 starts of 20 that deadlock there.
    verify = VerifyPlan(targets=("hexagon",), robots=40, seeds=(2,), explore=False, rank=0, more=())


class Song2016SubtreeClockController(Song2016Controller):
    """:class:`Song2016Controller` whose relocate robot counts its movement timeout from the step
    its own ``subtree`` marker was set (Algorithm 1 line 29), not from its confirmation as the
    relocate robot: :class:`Song2016SubtreeClock`.

    The marker is set in the step the robot's relocateID became its own ID (line 29: ``myID =
    myMsg.relocateID``), which is the step ``relocate_since`` records; so a confirmed relocate
    robot whose ``mover_since`` is later is moved back to ``relocate_since``.  Every other rule
    (the subtree robots' movement timeout, Def. 10's communication timeouts, the motion) is the
    default's.  The state snapshot's ``mover_since`` shows the clock used; the memoisation of
    :class:`Song2016Controller` (``repeat_step``, ``repeat_horizon``) reads that same clock, so
    traces with and without it are identical (tested).
    """

    __slots__ = ()

    def _take_roles(self, msg: Song2016Message, t: int) -> tuple[bool, str | None, bool, bool]:
        relocate, mover, may_move, changed = super()._take_roles(msg, t)
        if mover == "relocate" and self.relocate_since < self.mover_since:
            self.mover_since = self.relocate_since
            may_move = t - self.mover_since >= self.cfg.movement_timeout
        return relocate, mover, may_move, changed


class Song2016SubtreeClock(Song2016):
    """Song & O'Kane 2016 with the relocate robot's movement timeout counted from its own
    ``subtree`` marker (Song & O'Kane 2016, Alg. 1 line 29), concurrent with its communication
    timeout (Def. 10) instead of after it: a registered variant of ``song2016``, not its default.

    Line 29, "myMsg.subtree <- myID = myMsg.relocateID or parentMsg.subtree", puts the robot in
    the moving subtree as soon as it computes relocateID = myID; its movement timeout (Sec. VI)
    runs from then.  With both timeouts = n (Sec. VI) the relocate robot may move as soon as it
    is confirmed.  Everything else is :class:`Song2016`.  The text supports this reading: Thm. 13's proof counts
    one timeout per relocation ("T_i = T_timeout + T_wait + T_drive"; "bounded by the sum of the
    communication timeout, and the time spent actually moving to the vacancy, plus the total
    time waiting"), and Sec. VI ties the movement timeout to being "supposed to move".  It is a
    variant, not the default (docs/decisions.md, "Table III's steps"): its square runs at v = 0.6
    take 1.00 / 0.96 / 0.91 / 0.82x Table III's steps for n = 10 / 20 / 30 / 40, within 1.2x
    read both ways at three sizes of four, never at n = 40, and its ratio falls with n where the
    paper's does not; the default's two timeouts per relocation are what Sec. VI lists ("a
    communication timeout [...], and an movement timeout if it is supposed to move").  Its
    final formation is the default's (the sequential fill, Table II); only the steps differ
    (docs/song2016.md, "Where Table III's steps go").

    >>> from swarmproof.models.library import load
    >>> alg = Song2016SubtreeClock(n_robots=4)
    >>> c = alg.controller(1, Params(range=1.2, v=0.05), load("square"), None)
    >>> alg.name, alg.reading, type(c).__name__
    ('song2016-subtree-clock', '1', 'Song2016SubtreeClockController')
    """

    name = "song2016-subtree-clock"
    controller_class = Song2016SubtreeClockController
    #: verify: the default's ``algorithms`` runs (the same starts), so that each row stands beside
    #: song2016's (about 5 CPU-s).  No ``exploration`` rows: at 15 examples they took 31 CPU-s and
    #: missed the tree_links break, at 50 examples 98 CPU-s (docs/ci.md, "Changes to the shipped
    #: baseline"); the break shows in the square n = 20 row, as the default's does.
    verify = VerifyPlan(targets=("square", "hexagon", "octagon-square"), robots=10, seeds=(0, 1, 2),
                        explore=False, rank=0, more=(("square", 20, (1,)),))
