"""Exact checks that Lee & Chong's pattern targets are pairwise distinct (003 Table 1, Algs. 2-3).

A formation pattern ``F = {f_k}`` gives each robot its own target point (003 Sec. 2.1);
two IDs with one target would put two robots on one spot.  This module decides,
for a pattern and a team size ``n``, whether the targets that
:func:`swarmproof.models.line_patterns.target_points` computes are pairwise
distinct -- exactly, never by comparing floats:

* multi-line (003 Alg. 3): targets are ``(u_l - a d_u, b d_u)`` with integers
  ``a, b`` (:func:`~swarmproof.models.line_patterns.multi_line_offsets`);
  distinct iff the integer pairs are.
* wedge, horizontal and vertical line (Table 1 with Alg. 2): ``f - (u_l, 0)`` is
  ``j d_u (-cos a*, mark sin a*)``, ``(0, j d_u mark)`` or ``(j d_u mark, 0)`` with
  ``j = floor((ID+1)/2)`` and ``0 < a* < 90``: distinct iff ``(j, mark)`` differ
  (any mark when ``j = 0``).
* circle-type (circle, arc, fan-shape, k-polygons): with ``sigma = mark * theta``
  (degrees, an exact Fraction) and radius ``L > 0``, Table 1's ``T = u_l - L``
  gives ``f - (u_l, 0) = L (cos sigma - 1, sin sigma) = 2 L sin(sigma/2) (-sin(sigma/2),
  cos(sigma/2))``: the zero vector iff ``sigma = 0 (mod 360)``, otherwise a vector
  of direction ``sigma/2 + 90`` in (90, 270) degrees; the fixed-centre reading gives
  ``c + L (cos sigma, sin sigma)``.  Every family has ``theta`` in [0, 180] strictly
  increasing with ``j``, and ``L`` a function of ``j``; so two targets coincide iff
  their ``sigma`` agree modulo 360.  Signs and zeros of Table 1's ``k_m`` are decided
  exactly too (cosine of a rational number of degrees against 90 and 270); a
  non-positive radius (polygons with k <= 2 only) makes the criterion not apply:
  inconclusive.  A formula that divides by zero (k_m = 0/0 for ``k = 2`` at ID 0,
  ``j mod floor(n/k)`` with ``n < k`` in the integer index reading) is reported
  as undefined (status inconclusive, with the reason and the ID).

Examples
--------
>>> check_distinct("circle", 12)["status"]
'held'
>>> r = check_distinct("polygon", 6, k=2)
>>> r["status"], r["undefined"]["id"]
('inconclusive', 0)
>>> check_distinct("three-column", 4)["notes"]
['Alg. 3 column type k=3 with n=4: NoLine = 2, so the robots form 2 columns (lines parallel to v), not 3']

References
----------
003 Table 1, Algorithms 2 and 3, Sec. 3.1 (docs/leechong-patterns.md has the results for n <= 64).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Iterable

from swarmproof.models import line_patterns as lp
from swarmproof.models.errors import UsageError

__all__ = ["check_distinct", "check_all", "summarize"]


def _cos_sign(deg: Fraction) -> int:
    """The exact sign of cos(deg) for a rational number of degrees."""
    f = Fraction(deg) % 360
    if f in (90, 270):
        return 0
    return 1 if (f < 90 or f > 270) else -1


def _keys_uni(name: str, n: int, p: dict) -> tuple[list, dict | None, str, list]:
    """Exact keys of the uni-line targets (equal keys <=> equal points), an undefined formula, the method, notes."""
    fam, k = lp.pattern_info(name)["family"], p.get("k")
    notes: list[str] = []
    keys = []
    if fam in ("wedge", "horizontal-line", "vertical-line"):
        for i in range(n):
            j, mark = (i + 1) // 2, (1 if i % 2 == 0 else -1)
            keys.append((j, mark if j else 0))
        method = ("f - (u_l, 0) = j d_u (direction fixed by mark, nonzero for 0 < alpha* < 90): "
                  "compare integers (j, mark)")
        return keys, None, method, notes
    theta_mark = []
    for i in range(n):
        j, mark = (i + 1) // 2, (1 if i % 2 == 0 else -1)
        alpha = Fraction(360, n) * j
        if fam == "circle":
            theta = alpha
        elif fam == "arc":
            theta = alpha / p["m"]
        elif fam == "fan-shape":
            theta = 180 - alpha / p["m"]
        else:
            try:
                x = lp.polygon_index_angle(j, n, k, index=p["index"], rotation=p["rotation"])
            except ZeroDivisionError as exc:
                return [], {"id": i, "reason": str(exc)}, "", notes
            num, den = _cos_sign(Fraction(180, k)), _cos_sign(Fraction(180, k) - x)
            if den == 0:
                return [], {"id": i, "reason": f"k_m = cos(180/k) / cos(180/k - {x}) with k={k}: "
                                               f"the denominator is 0{' (and so is the numerator)' if num == 0 else ''}"}, "", notes
            if num * den <= 0:
                return None, None, (f"ID {i}: k_m = cos(180/k) / cos(180/k - {x}) with k={k} is "
                                    f"{'zero' if num == 0 else 'negative'}: the radius criterion does not apply"), notes
            theta = alpha
        theta_mark.append((theta, mark))
        keys.append((mark * theta) % 360)
    if fam == "fan-shape":
        notes.append("Table 1 puts the leader (ID 0, theta = 180) at (u_l - 2L, 0), not at its own "
                     "position (u_l, 0), although 003 Sec. 3.2 keeps the leader stationary")
    if fam == "polygon" and n % k:
        notes.append(f"n={n} is not a multiple of k={k}: only some of the {k} vertices hold a robot")
    method = ("sigma = mark * theta (exact degrees) mod 360, radius L > 0 decided exactly: "
              "equal targets <=> equal sigma")
    return keys, None, method, notes


def check_distinct(name: str, n: int, **params) -> dict:
    """Are the ``n`` targets of pattern ``name`` pairwise distinct?  Decided exactly.

    Parameters
    ----------
    name : str
        A pattern of :data:`~swarmproof.models.line_patterns.PATTERN_NAMES` (or a family
        of ``GENERIC_NAMES`` with ``k``).
    n : int
        The number of robots (>= 1).
    **params
        The pattern's parameters and readings (``pattern_info(name)["params"]``).

    Returns
    -------
    dict
        ``pattern, n, params, status`` ("held" | "violated" | "inconclusive"),
        ``method`` (the exact criterion), ``collisions`` (lists of IDs sharing a
        target, when violated), ``undefined`` (``{id, reason}`` when a formula is
        undefined), ``reason`` (why inconclusive), ``notes`` (other findings:
        fewer lines than named, the fan's leader, unoccupied vertices).

    Examples
    --------
    >>> check_distinct("two-row", 5)["status"], check_distinct("hexagon", 5, index="integer")["status"]
    ('held', 'inconclusive')
    """
    info = lp.pattern_info(name)
    n = lp._check_n(n)
    p = lp._params(name, params)
    out = {"pattern": name, "n": n, "params": dict(params), "status": None, "method": "", "collisions": [],
           "undefined": None, "reason": None, "notes": []}
    if info["type"] == "multi":
        offs = lp.multi_line_offsets(name, n, **params)
        keys = [tuple(o) for o in offs]
        out["method"] = "Alg. 3 targets are (u_l - a d_u, b d_u) with integers a, b: compare (a, b)"
        noline = lp.line_count(name, n, reading=p["noline"], **{k: v for k, v in params.items() if k != "noline"})
        ranks = len({a for a, _ in offs})
        files = len({b for _, b in offs})
        k = p["k"]
        if info["family"] == "columns" and ranks != k:
            out["notes"].append(f"Alg. 3 column type k={k} with n={n}: NoLine = {noline}, so the robots form "
                                f"{ranks} columns (lines parallel to v), not {k}")
        if info["family"] == "rows" and files != k:
            out["notes"].append(f"Alg. 3 row type k={k} with n={n}: the robots form {files} rows "
                                f"(lines parallel to u), not {k} (Sec. 3.2: only if n is more than NoLine)")
    else:
        keys, undefined, method, notes = _keys_uni(name, n, p)
        out["notes"] += notes
        out["method"] = method
        if undefined is not None:
            out.update(status="inconclusive", undefined=undefined,
                       reason=f"the formula is undefined at ID {undefined['id']}: {undefined['reason']}")
            return out
        if keys is None:
            out.update(status="inconclusive", reason=method, method="")
            return out
    groups: dict = {}
    for i, key in enumerate(keys):
        groups.setdefault(key, []).append(i)
    out["collisions"] = [ids for ids in groups.values() if len(ids) > 1]
    out["status"] = "violated" if out["collisions"] else "held"
    return out


def check_all(max_n: int = 64, patterns: Iterable | None = None) -> list[dict]:
    """:func:`check_distinct` for every pattern and every ``n = 2..max_n``.

    ``patterns``: names, or ``(name, params)`` pairs (default: every name of
    ``PATTERN_NAMES`` with its default parameters).

    >>> rows = check_all(8)
    >>> len(rows) == len(lp.PATTERN_NAMES) * 7, {r["status"] for r in rows}
    (True, {'held'})
    """
    if isinstance(max_n, bool) or not isinstance(max_n, int) or max_n < 2:
        raise UsageError(f"max_n={max_n!r} must be an integer >= 2", fix="e.g. max_n=64")
    items = [(p, {}) if isinstance(p, str) else (p[0], dict(p[1]))
             for p in (lp.PATTERN_NAMES if patterns is None else patterns)]
    return [check_distinct(name, n, **params) for name, params in items for n in range(2, max_n + 1)]


def summarize(rows: list[dict]) -> list[dict]:
    """One line per (pattern, params): the n where targets collide, are undefined or undecided,
    and the n with notes.

    >>> summarize(check_all(4, ["wedge"]))[0]["violated"]
    []
    """
    out: dict = {}
    for r in rows:
        key = (r["pattern"], tuple(sorted(r["params"].items())))
        s = out.setdefault(key, {"pattern": r["pattern"], "params": r["params"], "n": [], "held": [],
                                 "violated": [], "undefined": [], "inconclusive": [], "noted": []})
        s["n"].append(r["n"])
        if r["undefined"] is not None:
            s["undefined"].append(r["n"])
        else:
            s[r["status"]].append(r["n"])
        if r["notes"]:
            s["noted"].append(r["n"])
    return list(out.values())
