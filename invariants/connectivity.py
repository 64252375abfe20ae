"""Connectivity of the communication graph, and survival of spanning-tree links.

* :func:`connected_throughout`: if the communication graph (neighbors
  strictly closer than phi) is connected at the start, it is connected after
  every step (001 Lemma 11).
* :func:`first_disconnection`: the first step at which it is not, with its
  components.
* :func:`tree_links_survive`: every child-parent link of the spanning tree a
  step decided is still a neighbor pair after the step moved the robots
  (the mechanism of 001 Lemma 11's proof: NCLB keeps each child in range of
  its parent, Lemma 7 and Def. 8).  Parents are read from the controllers'
  states under the documented key ``"parent"`` (an ID or None;
  :func:`~swarmproof.invariants.result.state_value`).

Blind spots: poses are checked at step ends only (a link broken and restored
within one step cannot be seen, though straight-line motion makes that
impossible for two robots moving at most v*dt each from a distance < phi - v dt);
robots absent from the trace (crashed) are left out.

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III-A (range), Lemma 7,
Def. 8, Lemma 11.

Examples
--------
>>> import numpy as np
>>> from swarmproof.models.trace import Trace
>>> poses = np.array([[[0, 0, 0], [0.5, 0, 0]], [[0, 0, 0], [1.5, 0, 0]]], dtype=float)
>>> t = Trace(ids=[4, 9], poses=poses, states=[(None, (("parent", 4),))] * 2)
>>> first_disconnection(t, 1.0)
(1, [[4], [9]])
>>> connected_throughout(t, 1.0).witness
{'step': 1, 'components': [[4], [9]]}
>>> tree_links_survive(t, 1.0).witness["child"]
9
"""

from __future__ import annotations

import numpy as np

from swarmproof.models.sensing import INCLUSIVE_SLACK, components, neighbor_pairs, pair_distances

from .result import InvariantResult, state_value

__all__ = ["first_disconnection", "connected_throughout", "tree_links_survive", "components_at",
           "TREE_LINK_MODES", "DEFAULT_TREE_LINK_MODE", "tree_link_mode_of"]

LEMMA_11 = "001 Lemma 11 (connectivity is preserved)"


def components_at(trace, t: int, phi: float, inclusive: bool = False) -> list[list[int]]:
    """Components (as sorted lists of robot IDs) of the communication graph in recorded frame ``t``
    (after ``t`` steps on a dense trace; neighbors strictly closer than ``phi``, ``inclusive``: at
    most ``phi``)."""
    mask = trace.present_at(t)
    idx = np.flatnonzero(mask)
    xy = trace.poses[t][idx, :2]
    i, j, _ = neighbor_pairs(xy, phi, inclusive)
    ids = trace.ids[idx]
    comps = [sorted(int(ids[k]) for k in c) for c in components(len(idx), i, j)]
    return sorted(comps, key=lambda c: c[0])


def first_disconnection(trace, phi: float, inclusive: bool = False):
    """``(step, components)`` of the first disconnected step, or None if never.

    Steps whose poses and presence equal the previous step's are skipped (same
    graph).  Step 0 counts: a disconnected start returns ``(0, ...)``.
    """
    prev = None
    for i in range(len(trace.poses)):      # recorded frames; the step returned is the engine's
        cur = (trace.poses[i], trace.present_at(i))
        if prev is not None and np.array_equal(cur[0], prev[0]) and np.array_equal(cur[1], prev[1]):
            continue
        prev = cur
        comps = components_at(trace, i, phi, inclusive)
        if len(comps) > 1:
            return trace.time_of(i), comps
    return None


def _trace_inclusive(trace, inclusive):
    if inclusive is None:
        return (trace.meta.get("model") or {}).get("neighbor_rule") == "inclusive"
    return bool(inclusive)


def _feed(monitor, trace):
    """Feed every recorded step of ``trace`` to a streaming monitor; returns it."""
    monitor.start(trace.ids)
    for i in range(len(trace.poses)):      # recorded frames, named by their engine step
        monitor.observe(trace.time_of(i), trace.poses[i], trace.states[i], trace.present_at(i))
    return monitor


#: Teams at least this large keep a spanning-tree certificate (:class:`ConnectivityMonitor`): below,
#: the components of a few dozen pairs cost less than building a tree that a moving team breaks
#: (verify's exploration of 3-8 robots took 8 % more CPU with the certificate than without).
TREE_MIN_ROBOTS = 16


class ConnectivityMonitor:
    """Streaming form of :func:`connected_throughout`: ``observe`` every step, in order.

    The engine calls it on every step whatever it records (``simulate(observers=...)``),
    so a split at a step a sparse trace does not keep is still found.  Steps whose poses
    and presence equal the previous step's are skipped (same graph).  While the graph of a team of
    :data:`TREE_MIN_ROBOTS` or more is connected, a spanning tree of it (its shortest edges) is kept: a step that leaves every
    tree edge a neighbour pair, with the same robots present, is still connected and needs no
    components (n - 1 distances instead of every pair; the verdict is the same).
    """

    name = "connectivity"

    def __init__(self, phi: float, inclusive: bool = False, *, what: str = "steps") -> None:
        self.phi, self.inclusive, self.what = float(phi), bool(inclusive), what
        self.ids = None
        self._prev = None
        self._tree = None          # (present, rows i, rows j): a spanning tree of the last connected graph
        self._certified = 0        # instants the current tree answered
        self._backoff = 0          # trees that broke at once make the next one wait this many full checks
        self._wait = 0
        self.start_components = None
        self.hit = None
        self.count = 0

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)

    def observe(self, t, poses, states, present) -> None:
        self.count += 1
        if self.hit is not None or (self.start_components is not None and len(self.start_components) > 1):
            return
        if self._prev is not None and np.array_equal(poses, self._prev[0]) and np.array_equal(present, self._prev[1]):
            return
        self._prev = (np.array(poses, copy=True), np.array(present, copy=True))
        if self._tree is not None:
            if self._tree_holds(poses, present):
                self._certified += 1
                return
            # a tree that broke at once (robots at the edge of the range) is not worth its cost at
            # every instant: the next one waits 1, 2, 4 ... 64 full checks
            self._backoff = min(2 * self._backoff or 1, 64) if self._certified < 4 else 0
            self._wait = self._backoff
            self._tree = None
        idx = np.flatnonzero(present)
        xy = np.asarray(poses)[idx, :2]
        i, j, d = neighbor_pairs(xy, self.phi, self.inclusive)
        ids = self.ids[idx]
        comps = sorted((sorted(int(ids[k]) for k in c) for c in components(len(idx), i, j)), key=lambda c: c[0])
        if self.start_components is None:
            self.start_components = comps
        elif len(comps) > 1:
            self.hit = (int(t), comps)
        if len(comps) == 1 and self._wait == 0 and len(idx) >= TREE_MIN_ROBOTS:
            self._tree, self._certified = _spanning_tree(len(idx), i, j, d, idx, self._prev[1]), 0
        self._wait = max(self._wait - 1, 0)

    def _tree_holds(self, poses, present) -> bool:
        """Whether every edge of the last connected graph's spanning tree is still a neighbour pair
        (same robots present): then the graph is still connected, and its components need not be
        computed.  The distances are :func:`neighbor_pairs`' own (``pair_distances``, the same
        strict or inclusive test), so the answer is the one a full computation would give."""
        mask, ti, tj = self._tree
        if not np.array_equal(present, mask):
            return False
        if len(ti) == 0:
            return True
        d = pair_distances(np.asarray(poses, dtype=float)[:, :2], ti, tj)
        return bool(np.all(d <= self.phi * INCLUSIVE_SLACK) if self.inclusive else np.all(d < self.phi))

    def result(self) -> InvariantResult:
        start = self.start_components or []
        if len(start) > 1:
            return InvariantResult("connectivity", "inconclusive", LEMMA_11, None,
                                   f"vacuous: the start is disconnected ({len(start)} components)",
                                   applicable=False)
        if self.hit is None:
            return InvariantResult("connectivity", "held", LEMMA_11, None,
                                   f"connected at all {self.count} {self.what}")
        t, comps = self.hit
        return InvariantResult("connectivity", "violated", LEMMA_11, {"step": t, "components": comps},
                               f"the communication graph splits after step {t} into {len(comps)} "
                               f"components: {comps}")


def _spanning_tree(n: int, i, j, d, idx, present):
    """``(present, rows i, rows j)`` of a spanning tree of a connected neighbour graph on ``n``
    robots (edges ``i < j`` of the present robots ``idx``, distances ``d``): its shortest edges
    (a minimum spanning tree), the ones furthest from breaking, as rows of the poses."""
    if n - 1 == 0 or len(i) == n - 1:
        ti, tj = np.asarray(i, dtype=np.intp), np.asarray(j, dtype=np.intp)
    else:
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import minimum_spanning_tree

        # weights 1 + d: positive (a zero would read as no edge); the same order of edges
        mst = minimum_spanning_tree(coo_matrix((1.0 + np.asarray(d, dtype=float), (i, j)), shape=(n, n))).tocoo()
        if mst.nnz != n - 1:
            return None
        ti = np.minimum(mst.row, mst.col).astype(np.intp)
        tj = np.maximum(mst.row, mst.col).astype(np.intp)
    return np.array(present, copy=True), idx[ti], idx[tj]


def connected_throughout(trace, phi: float, inclusive: bool | None = None) -> InvariantResult:
    """The communication graph is connected at every step when it was at the start (Lemma 11).

    Neighbors are strictly closer than ``phi`` unless the run's robot model
    declares ``neighbor_rule="inclusive"`` (``trace.meta["model"]``) or
    ``inclusive`` says so.  A disconnected start makes the claim vacuous:
    ``inconclusive`` (``applicable=False``), never a pass.
    """
    mon = ConnectivityMonitor(phi, _trace_inclusive(trace, inclusive), what="recorded steps")
    return _feed(mon, trace).result()


TREE_LINK_MODES = ("decided", "standing", "persistent")

#: Every link of the tree each step decided, newly chosen ones included (issue 19):
#: the tree 001 Lemma 11's proof is about is the one the algorithm employs at time t.
DEFAULT_TREE_LINK_MODE = "decided"


def tree_link_mode_of(algorithm, options=None) -> str:
    """The reading of "the links of step t" for ``algorithm``: the property option
    ``tree_link_mode`` (``--tree-link-mode`` of simulate and explore), else the class attribute
    ``tree_link_mode``, else :data:`DEFAULT_TREE_LINK_MODE`.

    >>> tree_link_mode_of(object()), tree_link_mode_of(object(), {"tree_link_mode": "persistent"})
    ('decided', 'persistent')
    """
    mode = (options or {}).get("tree_link_mode") or getattr(algorithm, "tree_link_mode", None)
    return DEFAULT_TREE_LINK_MODE if mode is None else mode


def tree_links_survive(trace, phi: float, key: str = "parent", mode: str = DEFAULT_TREE_LINK_MODE) -> InvariantResult:
    """The spanning-tree links of each step survive the step's motion.

    Which links are "the links of step t" depends on when an algorithm's
    robots learn about them (the trace records ``states[t]`` before step t
    and ``states[t+1]`` after it decided):

    * ``"decided"`` (default): the parent every robot holds after step t
      decided (``states[t+1]``), links chosen in that very step included --
      the tree the algorithm employs at time t, which 001 Lemma 11's proof
      says survives the step.  A child that chose a parent in step t cannot
      be among that parent's children yet when messages take one step
      (song2016): NCLB does not protect such a link, and a break of one is
      reported with ``newly_chosen: true`` (a gap in 001's proof, which
      ignores the one-step lag; docs/song2016.md).
    * ``"standing"``: the parent a robot had before step t (``states[t]``):
      the parent has heard of its child by then (messages take one step), so
      NCLB (001 Sec. V-C, Def. 8) can protect the link in step t.
    * ``"persistent"``: links in both.  Blind spot: a link that breaks in the
      step in which the child first names that parent is not seen (the
      default until issue 19; it hid song2016's newly-chosen-link breaks).

    A link is checked when the two robots were neighbors at ``poses[t]``; it
    must still be a neighbor pair at ``poses[t+1]``.  Links to a robot that
    was not a neighbor are counted in ``detail["unsensed_parents"]``.
    """
    return _feed(TreeLinkMonitor(phi, key, mode), trace).result()


class TreeLinkMonitor:
    """Streaming form of :func:`tree_links_survive` (``observe`` every step, in order)."""

    name = "tree_links"

    def __init__(self, phi: float, key: str = "parent", mode: str = DEFAULT_TREE_LINK_MODE) -> None:
        if mode not in TREE_LINK_MODES:
            from swarmproof.models.errors import UsageError

            raise UsageError(f"tree_link_mode={mode!r} is not a reading of the tree links",
                             fix=f"use one of {TREE_LINK_MODES!r}")
        self.phi, self.key, self.mode = float(phi), key, mode
        self.ids = None
        self.slot: dict = {}
        self._prev = None
        self.checked = self.unsensed = 0
        self.any_parent = False
        self.longest = 0.0   # the longest checked link after its step, as a fraction of phi
        self.hit = None

    def start(self, ids) -> None:
        self.ids = np.asarray(ids)
        self.slot = {int(i): k for k, i in enumerate(self.ids.tolist())}

    def observe(self, t, poses, states, present) -> None:
        if self.hit is not None:
            return
        prev = self._prev
        # the parents of this step, read once (a states sequence may offer ``values_of(key)``, the
        # vectorised paths' fast column read); the states themselves are not kept past their step
        column = getattr(states, "values_of", None)
        key = self.key
        parents = column(key) if callable(column) else [state_value(s, key) for s in states]
        self._prev = (int(t), np.array(poses, copy=True), parents, np.array(present, copy=True))
        if prev is None:
            return
        t0, p0, before, pres0 = prev
        _, p1, after, pres1 = self._prev
        mode, phi = self.mode, self.phi
        for k in range(len(self.ids)):
            pb = before[k]
            pa = after[k]
            if mode == "decided":
                par = pa
            elif mode == "standing":
                par = pb
            else:
                par = pa if pa == pb else None
            if pa is not None or pb is not None:
                self.any_parent = True
            if par is None:
                continue
            q = self.slot.get(int(par))
            if q is None or not (pres0[k] and pres0[q] and pres1[k] and pres1[q]):
                continue
            d0 = float(np.hypot(*(p0[q, :2] - p0[k, :2])))
            if not d0 < phi:
                self.unsensed += 1
                continue
            self.checked += 1
            d1 = float(np.hypot(*(p1[q, :2] - p1[k, :2])))
            self.longest = max(self.longest, d1 / phi)
            if not d1 < phi:
                self.hit = (t0, int(self.ids[k]), int(par), d0, d1, pa != pb and par == pa)
                return

    def result(self) -> InvariantResult:
        key, mode, phi = self.key, self.mode, self.phi
        detail = {"links_checked": self.checked, "unsensed_parents": self.unsensed,
                  "longest_link_ratio": self.longest}
        if self.hit is not None:
            t, child, par, d0, d1, new = self.hit
            why = (f"; {child} chose {par} as its parent in this very step, so {par} could not yet "
                   "count it among its children (messages take one step): a link 001's proof of "
                   "Lemma 11 does not consider" if new else "")
            return InvariantResult(
                "tree_links", "violated", LEMMA_11,
                {"step": t, "child": child, "parent": par, "distance_before": d0,
                 "distance_after": d1, "mode": mode, "newly_chosen": bool(new)},
                f"step {t}: the link child {child} -> parent {par} broke "
                f"(distance {d0:.6g} -> {d1:.6g}, range {phi:g}; {mode} links){why}",
                detail=detail)
        if not self.any_parent:
            # vacuous: nothing to check is never a pass (DESIGN.md section 1, "Verdicts")
            return InvariantResult("tree_links", "inconclusive", LEMMA_11, None,
                                   f"vacuous: no controller state has a {key!r} entry (the algorithm keeps no "
                                   "spanning tree, or the run ended before any robot chose a parent)",
                                   applicable=False)
        if self.checked == 0:
            return InvariantResult("tree_links", "inconclusive", LEMMA_11, None,
                                   f"vacuous: no tree link was between neighbors at the start of a step ({mode} "
                                   f"links; {self.unsensed} to robots out of range)", applicable=False,
                                   detail=detail)
        return InvariantResult("tree_links", "held", LEMMA_11, None,
                               f"{self.checked} link-steps checked ({mode} links), none broke",
                               detail=detail)


def range_graph_applies(algorithm) -> bool:
    """Whether the range graph is the algorithm's communication graph: not when every robot
    hears every robot (``model.communication == "all"``, e.g. 002 Sec. III-A), where the
    communication graph is complete and cannot split.

    >>> from swarmproof.reference_impl.protocol import RobotModel
    >>> range_graph_applies(type("A", (), {"model": RobotModel(communication="all")})())
    False
    """
    return getattr(getattr(algorithm, "model", None), "communication", "neighbors") != "all"


def complete_graph_result() -> InvariantResult:
    """The connectivity verdict for an algorithm whose robots all hear each other:
    inconclusive and not applicable (a check that cannot fail is no check)."""
    return InvariantResult("connectivity", "inconclusive", LEMMA_11, None,
                           "not applicable: every robot hears every robot (communication='all'), so the "
                           "communication graph is complete; no range graph to split", applicable=False)


class CompleteGraphMonitor:
    """The streaming counterpart of :func:`complete_graph_result` (observes nothing)."""

    name = "connectivity"

    def start(self, ids) -> None:
        pass

    def observe(self, t, poses, states, present) -> None:
        pass

    def result(self) -> InvariantResult:
        return complete_graph_result()


def judge_connectivity(trace, phi: float, algorithm) -> InvariantResult:
    """The connectivity verdict of one run of ``algorithm``: :func:`connected_throughout` on its
    range graph, or :func:`complete_graph_result` when every robot hears every robot."""
    if not range_graph_applies(algorithm):
        return complete_graph_result()
    return connected_throughout(trace, phi)


def connectivity_monitor(algorithm, phi: float):
    """The streaming judge of :func:`judge_connectivity` for ``algorithm`` at range ``phi``
    (its model's neighbor rule decides strict or inclusive neighbours)."""
    if not range_graph_applies(algorithm):
        return CompleteGraphMonitor()
    model = getattr(algorithm, "model", None)
    return ConnectivityMonitor(float(phi), getattr(model, "neighbor_rule", "strict") == "inclusive")
