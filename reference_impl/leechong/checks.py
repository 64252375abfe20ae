"""Exact integer checks of Lee & Chong's (003) ID and neighbor formulas, for every n up to a bound.

003's Algorithms 1 and 4 are integer formulas; they are checked here by exhaustive
enumeration (exact: integers only, no floating point), for every team size
``n = 2..max_n`` (default 64) and every way the ``n - 1`` followers split between
the two half planes of Alg. 1 (``a`` with ``v >= 0``, ``b = n - 1 - a`` with ``v < 0``):

* :func:`id_formula` -- Alg. 1's printed formula (``2 x rank`` / ``2 x rank - 1``, the
  rank within the half plane) and the prose's numbering ("by turns ... then
  consecutively", Sec. 2.1): which splits give a bijection onto 1..n-1;
* :func:`neighbor_links` -- Alg. 4's N_id for every allocated ID: ``0 <= N_id < ID`` and
  N_id itself allocated (DESIGN.md section 5: "N_id must be an allocated ID"), so the
  links form a tree rooted at the leader.

The pattern targets' distinctness (Table 1, Alg. 3) is checked by
:mod:`swarmproof.reference_impl.leechong.patterns_check`.

>>> id_formula(4)["non_bijective_splits"]
[[0, 3], [2, 1], [3, 0]]
>>> id_formula(4, "prose")["status"]
'held'
"""

from __future__ import annotations

__all__ = ["allocated_ids", "id_formula", "neighbor_links", "check_all", "MAX_N"]

MAX_N = 64


def allocated_ids(upper: int, lower: int, numbering: str = "formula") -> list:
    """The follower IDs Alg. 1 hands out when ``upper`` robots have ``v >= 0`` and ``lower`` have
    ``v < 0`` (the leader, 0, not included), in rank order: upper first, then lower.

    >>> allocated_ids(3, 1)
    [2, 4, 6, 1]
    >>> allocated_ids(3, 1, "prose")
    [2, 3, 4, 1]
    """
    if numbering == "formula":
        return [2 * r for r in range(1, upper + 1)] + [2 * r - 1 for r in range(1, lower + 1)]
    turns = min(upper, lower)
    up = [2 * j + 2 for j in range(turns)]
    lo = [2 * j + 1 for j in range(turns)]
    rest = list(range(2 * turns + 1, upper + lower + 1))
    return up + (rest if upper > turns else []) + lo + (rest if lower > turns else [])


def id_formula(n: int, numbering: str = "formula") -> dict:
    """Whether Alg. 1's numbering is a bijection onto 1..n-1 for every split of ``n - 1`` followers.

    Returns ``{"n", "numbering", "status": "held"|"violated", "non_bijective_splits": [[a, b], ...]}``.
    """
    bad = []
    for a in range(n):
        b = n - 1 - a
        ids = allocated_ids(a, b, numbering)
        if sorted(ids) != list(range(1, n)):
            bad.append([a, b])
    return {"n": n, "numbering": numbering, "status": "violated" if bad else "held", "non_bijective_splits": bad}


def neighbor_links(n: int, kind: str, k: int | None, numbering: str = "formula") -> dict:
    """Alg. 4 over every split: each allocated ID's N_id is allocated (or 0) and below it.

    ``kind`` "uni" or "multi" with ``k`` = NoLine of Alg. 4 line 7.  Returns ``{"status",
    "checked", "counterexample": {"n", "split", "id", "n_id", "why"} | None}``.
    """
    from .numbering import neighbor_id

    checked = 0
    for a in range(n):
        b = n - 1 - a
        ids = allocated_ids(a, b, numbering)
        have = set(ids) | {0}
        for rid in ids:
            checked += 1
            nid = neighbor_id(rid, kind, k)
            why = None
            if not 0 <= nid < rid:
                why = f"N_id={nid} is not in 0..ID-1"
            elif nid not in have:
                why = f"N_id={nid} is not an allocated ID (allocated: {sorted(have)})"
            if why:
                return {"status": "violated", "checked": checked,
                        "counterexample": {"n": n, "split": [a, b], "id": rid, "n_id": nid, "why": why}}
    return {"status": "held", "checked": checked, "counterexample": None}


def check_all(max_n: int = MAX_N) -> dict:
    """Every check for ``n = 2..max_n`` and every pattern of :mod:`swarmproof.models.line_patterns`.

    Returns ``{"max_n", "id_formula": {numbering: {"bijective_n": [...], "first_failures": [...]}},
    "neighbor_links": [{"pattern", "numbering", "status", "violated_n": [...], "first": {...}}]}``.
    """
    from swarmproof.models import line_patterns as lp

    out: dict = {"max_n": max_n, "id_formula": {}, "neighbor_links": []}
    for numbering in ("formula", "prose"):
        res = [id_formula(n, numbering) for n in range(2, max_n + 1)]
        out["id_formula"][numbering] = {
            "status": "violated" if any(r["status"] == "violated" for r in res) else "held",
            "always_bijective_n": [r["n"] for r in res if r["status"] == "held"],
            "first_failures": [r for r in res if r["status"] == "violated"][:3]}
    for name in lp.PATTERN_NAMES:
        uni = lp.pattern_info(name)["type"] == "uni"
        for numbering in ("formula", "prose"):
            bad, first = [], None
            for n in range(2, max_n + 1):
                k = None if uni else lp.line_count(name, n, reading="alg4")
                r = neighbor_links(n, "uni" if uni else "multi", k, numbering)
                if r["status"] == "violated":
                    bad.append(n)
                    first = first or r["counterexample"]
            out["neighbor_links"].append({"pattern": name, "numbering": numbering,
                                          "status": "violated" if bad else "held", "violated_n": bad,
                                          "first": first})
    return out


def verify_rows(max_n: int = MAX_N) -> list:
    """The checks as ``swarmproof verify`` rows (section ``formulas``): ``{subject, property,
    status ("proved" | "violated" | "inconclusive"), detail, cites, data}``.  Exhaustive over
    n = 2..max_n, so "proved" means proved for exactly those n (the subject says so)."""
    from swarmproof.reference_impl.leechong.patterns_check import check_all as distinct_all, summarize

    res = check_all(max_n)
    rows = []
    span = f"n=2..{max_n}"
    # Lee & Chong, Sec. 2.1 (the prose: the default, leechong-leader / leechong-neighbor since reading "2")
    # and Alg. 1 lines 11-14 (the printed formula: the -printed variants, issue 31)
    for numbering, label in (("formula", "Alg. 1 printed ID formula, leechong-leader-printed and -neighbor-printed"),
                             ("prose", "Alg. 1 ID prose numbering (Sec. 2.1), leechong-leader and -neighbor")):
        r = res["id_formula"][numbering]
        first = r["first_failures"][0] if r["first_failures"] else None
        if first is None:
            detail = f"a bijection onto 1..n-1 for every split of the followers between the half planes, {span}"
        else:
            a, b = first["non_bijective_splits"][0]
            ids = sorted(allocated_ids(a, b, numbering))
            k = first["n"] - 1
            detail = (f"not a bijection onto 1..n-1: smallest team n={first['n']} (the leader and {k} "
                      f"follower{'s' if k != 1 else ''}), split [upper, lower] = [{a}, {b}]: IDs {ids}; a bijection "
                      f"only when upper = lower or lower = upper + 1")
        rows.append({"subject": f"003 {label} ({span})", "property": "ids_bijective",
                     "status": "proved" if first is None else "violated", "detail": detail,
                     "cites": "003 Sec. 2.1, Alg. 1 lines 8-16", "data": {"numbering": numbering}})
    for r in res["neighbor_links"]:
        cx = r["first"]
        detail = (f"0 <= N_id < ID and N_id allocated, for every allocated ID and split, {span}" if cx is None else
                  f"n={cx['n']}, split {cx['split']}: ID {cx['id']} -> {cx['why']} (violated for n in "
                  f"{r['violated_n'][:6]}{'...' if len(r['violated_n']) > 6 else ''})")
        rows.append({"subject": f"003 Alg. 4 N_id, {r['pattern']}, {r['numbering']} IDs ({span})",
                     "property": "neighbor_tree", "status": "proved" if cx is None else "violated",
                     "detail": detail, "cites": "003 Alg. 4, Sec. 4.1", "data": {"counterexample": cx}})
    for s in summarize(distinct_all(max_n)):
        bad = s["violated"]
        und = s["undefined"] + s["inconclusive"]
        status = "violated" if bad else ("inconclusive" if und else "proved")
        detail = (f"targets pairwise distinct for every {span}" if status == "proved" else
                  f"two robots share a target for n in {bad[:6]}" if bad else
                  f"undefined or not decided exactly for n in {und[:6]}")
        rows.append({"subject": f"003 targets of {s['pattern']} ({span})", "property": "targets_distinct",
                     "status": status, "detail": detail, "cites": "003 Table 1, Algs. 2-3",
                     "data": {"params": s["params"]}})
    return rows
