"""What a property needs of an algorithm, and what an algorithm can give: "not applicable".

A property declares what it reads that not every algorithm has (its ``needs``, a tuple of the
names below); an algorithm declares what it can give through its robot model and its class
attributes, never through its name.  Where an algorithm cannot give what a property needs, the
property is *not applicable* to it: no verdict at all -- neither held nor inconclusive
(DESIGN.md section 1 "Verdicts", section 5 "Not applicable") -- and nothing is run to find it
out.  ``inconclusive`` stays for questions that were asked and not decided.

========================  ====================================================================
need                      an algorithm gives it when
========================  ====================================================================
``range_graph``           its robots hear only those within range phi: ``model.communication``
                          is ``"neighbors"`` or ``"none"`` (with ``"all"`` every robot hears
                          every robot: the communication graph is complete and cannot split)
``parent``                its controller states name a spanning-tree parent: ``"parent"`` in
                          its class attribute ``state_fields``
``messages``              its robots send messages: ``model.communication`` is not ``"none"``
``lattice_target``        it forms lattice graphs: the run's target is a lattice (before a run:
                          its ``explore_targets`` name one, or it names none, so the explorer
                          gives it the bundled lattices)
``premise_monitors``      it declares lemma premise monitors (class attribute ``premise_monitors``)
``invariants``            it declares runtime invariants (class attribute ``invariants``)
``completion``            its robots detect that the formation is complete and say so: it
                          declares the invariants that judge that detection (class attribute
                          ``completion_invariants``)
========================  ====================================================================

An algorithm that does not declare ``state_fields`` at all leaves ``parent`` undecided: the
property then runs, and a run that finds no parent is inconclusive (vacuous), as before.

Examples
--------
>>> from swarmproof.reference_impl.protocol import RobotModel
>>> A = type("A", (), {"model": RobotModel(communication="all"), "state_fields": ()})
>>> not_applicable(A(), ("range_graph", "parent"))
"no range graph: every robot hears every robot (communication='all'); no 'parent' field in its controller states (state_fields=())"
>>> B = type("B", (), {"model": RobotModel(), "state_fields": ("parent",)})
>>> not_applicable(B(), ("range_graph", "parent")) is None
True
>>> missing(type("C", (), {"model": RobotModel()})(), ("parent",))   # undeclared: not decided here
()
"""

from __future__ import annotations

from typing import Any, Callable

__all__ = ["NEEDS", "missing", "not_applicable", "gives", "NOT_APPLICABLE_STATUS"]

#: The status word of a not-applicable property in explore's and simulate's JSON.
NOT_APPLICABLE_STATUS = "not_applicable"


def _model(algorithm) -> Any:
    return getattr(algorithm, "model", None)


def _range_graph(algorithm, target) -> tuple[bool | None, str]:
    comm = getattr(_model(algorithm), "communication", "neighbors")
    return comm != "all", f"no range graph: every robot hears every robot (communication={comm!r})"


def _parent(algorithm, target) -> tuple[bool | None, str]:
    fields = getattr(algorithm, "state_fields", None)
    if fields is None:
        return None, ""
    fields = tuple(fields)
    return "parent" in fields, f"no 'parent' field in its controller states (state_fields={fields!r})"


def _messages(algorithm, target) -> tuple[bool | None, str]:
    comm = getattr(_model(algorithm), "communication", "neighbors")
    return comm != "none", f"no messages: its robots send none (communication={comm!r})"


def _lattice_target(algorithm, target) -> tuple[bool | None, str]:
    if target is not None:
        kind = getattr(target, "kind", "lattice")
        return kind == "lattice", f"no lattice target: the target is a {kind!r}"
    names = tuple(getattr(algorithm, "explore_targets", None) or ())
    if not names:
        return True, ""
    kinds = sorted({n.partition(":")[0] if ":" in n else "lattice" for n in names})
    return "lattice" in kinds, f"no lattice target: it forms {', '.join(kinds)} targets (explore_targets)"


def _premise_monitors(algorithm, target) -> tuple[bool | None, str]:
    return bool(getattr(algorithm, "premise_monitors", None)), "it declares no lemma premise monitors (premise_monitors)"


def _invariants(algorithm, target) -> tuple[bool | None, str]:
    return bool(getattr(algorithm, "invariants", None)), "it declares no runtime invariants (invariants)"


def _completion(algorithm, target) -> tuple[bool | None, str]:
    return (bool(getattr(algorithm, "completion_invariants", None)),
            "its robots do not detect completion (no completion_invariants)")


#: Every need a property may declare -> ``(algorithm, target) -> (gives: bool | None, why not)``
#: (None: the algorithm does not say; the property then runs).
NEEDS: dict[str, Callable[[Any, Any], tuple[bool | None, str]]] = {
    "range_graph": _range_graph,
    "parent": _parent,
    "messages": _messages,
    "lattice_target": _lattice_target,
    "premise_monitors": _premise_monitors,
    "invariants": _invariants,
    "completion": _completion,
}


def gives(algorithm, need: str, target=None) -> bool | None:
    """Whether ``algorithm`` (a class or an object) gives ``need``: True, False, or None when it
    does not declare it.  An unknown need is a ``ValueError``."""
    if need not in NEEDS:
        raise ValueError(f"need={need!r} is not one of {sorted(NEEDS)!r}")
    return NEEDS[need](algorithm, target)[0]


def missing(algorithm, needs, target=None) -> tuple[tuple[str, str], ...]:
    """``(need, why)`` of each of ``needs`` that ``algorithm`` declares it cannot give."""
    out = []
    for need in needs or ():
        if need not in NEEDS:
            raise ValueError(f"need={need!r} is not one of {sorted(NEEDS)!r}")
        ok, why = NEEDS[need](algorithm, target)
        if ok is False:
            out.append((need, why))
    return tuple(out)


def not_applicable(algorithm, needs_or_property, target=None) -> str | None:
    """Why the property (or its ``needs``) is not applicable to ``algorithm``, or None when it is
    (or may be: undeclared capabilities are left to the run).  ``needs_or_property`` is a
    :class:`~swarmproof.invariants.registry.Property` or a tuple of need names."""
    needs = getattr(needs_or_property, "needs", needs_or_property)
    gone = missing(algorithm, needs, target)
    return "; ".join(why for _, why in gone) if gone else None
