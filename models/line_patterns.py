"""Lee & Chong's formation patterns (003 Sec. 3.1-3.2, Table 1, Algorithms 2 and 3) as target points.

Every robot knows the common frame ``(u, v)`` of 003 Sec. 2.1 (``u`` from the
common origin to the leader, ``v`` 90 degrees counterclockwise), its ID
(0 = the leader, Algorithm 1) and the leader's coordinate ``u_l``; from the
pattern ``F`` it computes its own target ``f_i = (u_t,i, v_t,i)``:

* uni-line patterns (wedge, horizontal and vertical line, circle, arc,
  fan-shape, k-polygons): three parameters theta, L, T of Table 1, then
  003 Alg. 2 lines 4-5: ``u = cos(theta) L + T``, ``v = sin(theta) L mark``;
* multi-line patterns (k rows / k columns): 003 Alg. 3 (NoLine, then L,
  then lines 26-27: ``u = u_l - floor(ID / NoLine) d_u``, ``v = L mark``).

``mark`` is +1 for an even ID and -1 for an odd one (Alg. 2 lines 1-3,
Alg. 3 lines 23-25).  The functions here are pure; the readings chosen where
Table 1's extraction is garbled are parameters, the defaults recorded in
docs/decisions.md ("Lee & Chong patterns (issue 17)") and docs/leechong-patterns.md.

Examples
--------
>>> target_points("two-row", 4, 1.0).tolist()
[[0.0, 0.0], [0.0, -1.0], [-1.0, 0.0], [-1.0, -1.0]]
>>> pattern_info("hexagon")["type"], pattern_info("three-column")["params"]
('uni', {'noline': 'alg3'})
>>> interval_for_span(11.0, 12)
1.0

References
----------
003: Lee & Chong, "Decentralized formation control for small-scale robot teams with
anonymity", Mechatronics (/work/shared/seeds/003_8f3001202a798af8.txt), Secs. 2.1, 3.1,
3.2, 3.5, Table 1, Algorithms 2-4.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction
from typing import Any

import numpy as np

from .errors import UsageError

__all__ = ["PATTERN_NAMES", "GENERIC_NAMES", "pattern_info", "target_points", "target_of", "interval_for_span",
           "line_count", "uni_line_parameters", "multi_line_offsets", "polygon_index_angle"]

# name -> (type, family, fixed k or None, citation)
_PATTERNS: dict[str, tuple[str, str, int | None, str]] = {
    "wedge": ("uni", "wedge", None, "003 Table 1 (wedge), Alg. 2"),
    "horizontal-line": ("uni", "horizontal-line", None, "003 Table 1 (horizontal line), Alg. 2"),
    "vertical-line": ("uni", "vertical-line", None, "003 Table 1 (vertical line), Alg. 2"),
    "circle": ("uni", "circle", None, "003 Table 1 (circle), Alg. 2"),
    "arc": ("uni", "arc", None, "003 Table 1 (arc, m = 3 Sec. 3.1), Alg. 2"),
    "fan-shape": ("uni", "fan-shape", None, "003 Table 1 (fan-shape, m = 3 Sec. 3.1), Alg. 2"),
    "triangle": ("uni", "polygon", 3, "003 Table 1 (k-polygon, k = 3), Alg. 2"),
    "diamond": ("uni", "polygon", 4, "003 Table 1 (k-polygon, k = 4; Sec. 3.2 rotates it by theta), Alg. 2"),
    "pentagon": ("uni", "polygon", 5, "003 Table 1 (k-polygon, k = 5; Fig. 7), Alg. 2"),
    "pen": ("uni", "polygon", 5, "003 Fig. 10 'pen' read as the pentagon (k = 5), Table 1, Alg. 2"),
    "hexagon": ("uni", "polygon", 6, "003 Table 1 (k-polygon, k = 6), Alg. 2"),
    "one-row": ("multi", "rows", 1, "003 Alg. 3 (row type, k = 1; 'one row' Secs. 5.3, 6.2)"),
    "two-row": ("multi", "rows", 2, "003 Alg. 3 (row type, k = 2; Fig. 6, Sec. 4.2 'two row')"),
    "three-row": ("multi", "rows", 3, "003 Alg. 3 (row type, k = 3; Tables 2-5 'Three rows')"),
    "one-column": ("multi", "columns", 1, "003 Alg. 3 (column type, k = 1; 'one column' Sec. 6.2)"),
    "two-column": ("multi", "columns", 2, "003 Alg. 3 (column type, k = 2; Tables 2-5 'Two columns')"),
    "three-column": ("multi", "columns", 3, "003 Alg. 3 (column type, k = 3; Fig. 6, Sec. 4.2 'three column')"),
    # the families themselves, with k a parameter
    "polygon": ("uni", "polygon", None, "003 Table 1 (k-polygon), Alg. 2"),
    "rows": ("multi", "rows", None, "003 Alg. 3 (row type)"),
    "columns": ("multi", "columns", None, "003 Alg. 3 (column type)"),
}

#: The named patterns (bundled as ``lines:NAME`` targets), in the order of 003 Table 1 then Alg. 3.
PATTERN_NAMES: tuple[str, ...] = tuple(n for n in _PATTERNS if n not in ("polygon", "rows", "columns"))
#: Families that need ``k`` (not bundled; ``target_points("polygon", n, d_u, k=7)``).
GENERIC_NAMES: tuple[str, ...] = ("polygon", "rows", "columns")

_CHOICES = {"radius": ("arc-length", "printed"), "center": ("table", "fixed"),
            "index": ("rational", "integer"), "noline": ("alg3", "alg4")}


def _defaults(name: str) -> dict[str, Any]:
    typ, fam, k, _ = _PATTERNS[name]
    if fam == "wedge":
        return {"alpha_star": 30.0}
    if fam in ("horizontal-line", "vertical-line"):
        return {}
    if fam == "circle":
        return {"radius": "arc-length"}
    if fam in ("arc", "fan-shape"):
        return {"m": 3, "radius": "arc-length"}
    if fam == "polygon":
        d = {"radius": "arc-length", "center": "table", "index": "rational", "rotation": 0.0}
        return d if k is not None else {"k": None, **d}
    d = {"noline": "alg3"}
    return d if k is not None else {"k": None, **d}


def _check_name(name) -> str:
    if not isinstance(name, str) or name not in _PATTERNS:
        raise UsageError(f"pattern name={name!r} is not a Lee & Chong pattern",
                         fix=f"use one of {list(PATTERN_NAMES) + list(GENERIC_NAMES)!r}")
    return name


def pattern_info(name: str) -> dict:
    """What a pattern is: its type (``"uni"`` Alg. 2 + Table 1, ``"multi"`` Alg. 3), family,
    ``k`` (polygon sides, or rows / columns), citation and parameters with their defaults.

    >>> info = pattern_info("wedge")
    >>> info["type"], info["family"], info["params"]
    ('uni', 'wedge', {'alpha_star': 30.0})
    >>> pattern_info("diamond")["k"], pattern_info("two-column")["family"]
    (4, 'columns')
    """
    typ, fam, k, cites = _PATTERNS[_check_name(name)]
    return {"name": name, "type": typ, "family": fam, "k": k, "citation": cites, "params": _defaults(name)}


def interval_for_span(span: float, n: int) -> float:
    """The uniform interval ``d_u`` that keeps a pattern's ``span`` with ``n`` robots.

    003 Sec. 3.1: "the span ... is to multiply d_u by the number of n-1 robots", so
    ``d_u = span / (n - 1)``; Sec. 3.5 keeps the span when robots are lost.

    >>> interval_for_span(10.0, 6), interval_for_span(10.0, 5)
    (2.0, 2.5)
    """
    _check_n(n, least=2, what="a span needs at least two robots (d_u = span / (n - 1))")
    if isinstance(span, bool) or not isinstance(span, (int, float)) or not math.isfinite(span) or span <= 0:
        raise UsageError(f"span={span!r} must be a finite number > 0", fix="give the pattern's size, e.g. span=11.0")
    return float(span) / (n - 1)


def _check_n(n, least: int = 1, what: str = "") -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < least:
        raise UsageError(f"n={n!r} must be an integer >= {least}" + (f" ({what})" if what else ""),
                         fix="give the number of robots, e.g. n=12")
    return int(n)


def _check_k(name: str, k) -> int:
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
        raise UsageError(f"k={k!r} must be an integer >= 1 for pattern {name!r}",
                         fix="give the number of polygon sides / rows / columns, e.g. k=4")
    return int(k)


def _params(name: str, params: dict) -> dict:
    """The defaults overridden by ``params``, validated (UsageError naming name=value)."""
    base = _defaults(name)
    unknown = sorted(set(params) - set(base))
    if unknown:
        raise UsageError(f"{unknown[0]}={params[unknown[0]]!r} is not a parameter of pattern {name!r}",
                         fix=f"use only {sorted(base)!r}" if base else f"pattern {name!r} takes no parameters")
    p = {**base, **params}
    fixed_k = _PATTERNS[name][2]
    if "k" in p:
        if p["k"] is None:
            raise UsageError(f"k=None: pattern {name!r} needs k", fix="give k, e.g. k=4")
        p["k"] = _check_k(name, p["k"])
    elif fixed_k is not None:
        p["k"] = fixed_k
    for key, allowed in _CHOICES.items():
        if key in p and p[key] not in allowed:
            raise UsageError(f"{key}={p[key]!r} is not a reading of pattern {name!r}", fix=f"use one of {list(allowed)!r}")
    if "alpha_star" in p:
        a = p["alpha_star"]
        if isinstance(a, bool) or not isinstance(a, (int, float)) or not (0 < a < 90):
            raise UsageError(f"alpha_star={a!r} must be a number of degrees with 0 < alpha_star < 90 (003 Table 1)",
                             fix="e.g. alpha_star=30")
    if "m" in p:
        m = p["m"]
        if isinstance(m, bool) or not isinstance(m, (int, np.integer)) or m < 1:
            raise UsageError(f"m={m!r} must be an integer >= 1 (003 Sec. 3.1 uses m = 3)", fix="e.g. m=3")
    if "rotation" in p:
        r = p["rotation"]
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not math.isfinite(r):
            raise UsageError(f"rotation={r!r} must be a finite number of degrees", fix="e.g. rotation=45")
    return p


def line_count(name: str, n: int, reading: str = "alg3", **params) -> int:
    """``NoLine`` of a multi-line pattern: the number of lines parallel to the u-axis.

    ``reading="alg3"``: 003 Alg. 3 lines 1-9: row type ``k``; column type
    ``floor(n/k)`` when ``k`` divides ``n``, else ``floor(n/k) + 1`` (= ceil(n/k)).
    ``reading="alg4"``: 003 Alg. 4 line 7: ``NoLine := k`` for both types.

    >>> line_count("three-column", 12), line_count("three-column", 12, reading="alg4")
    (4, 3)
    >>> line_count("two-row", 7), line_count("columns", 7, k=2)
    (2, 4)
    """
    _check_name(name)
    n = _check_n(n)
    if _PATTERNS[name][0] != "multi":
        raise UsageError(f"name={name!r} is a uni-line pattern: NoLine is defined for multi-line ones (003 Alg. 3)",
                         fix=f"use one of {[m for m in _PATTERNS if _PATTERNS[m][0] == 'multi']!r}")
    if reading not in _CHOICES["noline"]:
        raise UsageError(f"reading={reading!r} is not a NoLine reading", fix="use 'alg3' or 'alg4'")
    k = _params(name, params)["k"]
    if reading == "alg4" or _PATTERNS[name][1] == "rows":
        return k
    return n // k if n % k == 0 else n // k + 1


def multi_line_offsets(name: str, n: int, **params) -> list[tuple[int, int]]:
    """003 Alg. 3 in exact integers: ``(a_i, b_i)`` with ``f_i = (u_l - a_i d_u, b_i d_u)``.

    ``a_i = floor(ID / NoLine)`` (line 26), ``b_i = L_i mark_i / d_u`` (lines 10-27).

    >>> multi_line_offsets("three-row", 6)
    [(0, 0), (0, -1), (0, 1), (1, 0), (1, 1), (1, -1)]
    """
    p = _params(name, params)
    noline = line_count(name, n, reading=p["noline"], **{k: v for k, v in params.items() if k != "noline"})
    return [_multi_offset(i, noline) for i in range(n)]


def _multi_offset(i: int, noline: int) -> tuple[int, int]:
    """003 Alg. 3 lines 10-27 for the robot with ID ``i``: ``(floor(ID / NoLine), L mark / d_u)``."""
    q, r = i % noline, i // noline
    if noline % 2 == 0:                 # Alg. 3 lines 10-11
        ell = (q + 1) // 2
    elif r % 2 == 0:                    # lines 13-14
        ell = (q + 1) // 2
    elif i % 2 == 0:                    # lines 16-17
        ell = (q + 2) // 2
    else:                               # lines 18-19
        ell = q // 2
    mark = 1 if i % 2 == 0 else -1      # lines 23-25
    return r, ell * mark


def polygon_index_angle(j: int, n: int, k: int, *, index: str = "rational", rotation=0) -> Fraction:
    """The angle (degrees, exact) in Table 1's k_m denominator: ``360/n * (j mod (n/k))``.

    Table 1 (k-polygon, garbled in the extraction) prints the index as
    ``j - n/k * floor(j / (n/k))`` with ``j = floor((ID+1)/2)``, i.e. ``j mod (n/k)``.
    ``index="rational"`` reads ``n/k`` as the exact quotient, so the angle is the polar
    angle ``alpha - rotation`` reduced modulo ``360/k``; ``index="integer"`` reads it as
    ``floor(n/k)`` (undefined when ``n < k``: ZeroDivisionError).  ``rotation`` (degrees,
    0 in Table 1) turns the polygon (003 Sec. 3.2: diamonds "by changing theta").

    >>> polygon_index_angle(4, 12, 3), polygon_index_angle(5, 12, 3)
    (Fraction(0, 1), Fraction(30, 1))
    >>> polygon_index_angle(3, 12, 5), polygon_index_angle(3, 12, 5, index="integer")
    (Fraction(18, 1), Fraction(30, 1))
    """
    if index == "integer":
        period = n // k
        if period == 0:
            raise ZeroDivisionError(f"j mod floor(n/k) with n={n}, k={k}: floor(n/k) = 0")
        return (Fraction(360, n) * j - Fraction(rotation)) % (Fraction(360, n) * period)
    return (Fraction(360, n) * j - Fraction(rotation)) % Fraction(360, k)


def _cos_sin(deg) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90 degrees (so hand-worked
    values such as a circle's ID n-1 at 180 degrees come out as written)."""
    f = Fraction(deg) % 360
    exact = {Fraction(0): (1.0, 0.0), Fraction(90): (0.0, 1.0), Fraction(180): (-1.0, 0.0), Fraction(270): (0.0, -1.0)}
    if f in exact:
        return exact[f]
    r = math.radians(float(f))
    return math.cos(r), math.sin(r)


def uni_line_parameters(name: str, n: int, i: int, d_u: float, u_l: float = 0.0, **params) -> dict:
    """Table 1's ``theta`` (degrees), ``L`` and ``T`` for the robot with ID ``i``, exactly as printed
    in the chosen reading, with ``theta_exact`` (theta as a Fraction of degrees), ``mark`` and
    ``j = floor((ID+1)/2)``.

    >>> p = uni_line_parameters("wedge", 5, 3, 1.0)
    >>> p["theta"], p["L"], p["T"]
    (-30.0, -2.0, 0.0)
    >>> uni_line_parameters("circle", 4, 1, 2 * math.pi)["L"]
    4.0
    """
    _check_name(name)
    typ, fam, _, _ = _PATTERNS[name]
    if typ != "uni":
        raise UsageError(f"name={name!r} is a multi-line pattern (003 Alg. 3), it has no Table 1 parameters",
                         fix=f"use one of {[m for m in _PATTERNS if _PATTERNS[m][0] == 'uni']!r}")
    p = _params(name, params)
    j = (i + 1) // 2                                   # floor((ID_i + 1) / 2)
    mark = 1 if i % 2 == 0 else -1
    d_o = d_u * j                                      # Table 1: d_o = d_u * floor((ID+1)/2)
    if fam == "wedge":
        a = Fraction(p["alpha_star"])
        return {"theta": -float(p["alpha_star"]), "L": -d_o, "T": u_l, "mark": mark, "j": j, "theta_exact": -a}
    if fam == "horizontal-line":
        return {"theta": 90.0, "L": d_o, "T": u_l, "mark": mark, "j": j, "theta_exact": Fraction(90)}
    if fam == "vertical-line":
        return {"theta": 0.0, "L": d_o * mark, "T": u_l, "mark": mark, "j": j, "theta_exact": Fraction(0)}
    alpha = Fraction(360, n) * j                       # alpha = 360/n * floor((ID+1)/2)
    if p["radius"] == "arc-length":
        d_c = n * d_u / (2 * math.pi)                  # arc length d_u between neighbours (Sec. 3.1)
    else:
        d_c = 360.0 * d_u / (2 * math.pi * n)          # Table 1 as printed, 360 deg read as the number 360
    if fam == "circle":
        L = d_c
        theta = alpha
    elif fam in ("arc", "fan-shape"):
        m = int(p["m"])
        L = m * d_c if p["radius"] == "arc-length" else d_c / m
        theta = alpha / m if fam == "arc" else 180 - alpha / m
    else:                                              # k-polygon
        k = p["k"]
        x = polygon_index_angle(j, n, k, index=p["index"], rotation=p["rotation"])
        den = math.cos(math.radians(180 / k - float(x)))
        num = math.cos(math.radians(180 / k))
        if abs(den) < 1e-12:
            raise ZeroDivisionError(f"k_m = cos(180/k)/cos(180/k - {float(x):g}) with k={k}: denominator 0")
        L = num / den * d_c
        theta = alpha
        if p["center"] == "fixed":
            x0 = polygon_index_angle(0, n, k, index=p["index"], rotation=p["rotation"])
            L0 = num / math.cos(math.radians(180 / k - float(x0))) * d_c
            return {"theta": float(theta), "L": L, "T": u_l - L0, "mark": mark, "j": j, "theta_exact": alpha}
    return {"theta": float(theta), "L": L, "T": u_l - L, "mark": mark, "j": j, "theta_exact": Fraction(theta)}


def _check_real(name: str, x) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.floating, np.integer)) or not math.isfinite(x):
        raise UsageError(f"{name}={x!r} must be a finite number")
    return float(x)


def target_points(name: str, n: int, d_u: float, u_l: float = 0.0, **params) -> np.ndarray:
    """Targets ``f_i = (u_t,i, v_t,i)`` of all ``n`` robots, row ``i`` for ID ``i`` (0 = leader).

    Uni-line: Table 1's (theta, L, T), then 003 Alg. 2 lines 4-5
    ``u = cos(theta) L + T``, ``v = sin(theta) L mark``.  Multi-line: 003 Alg. 3.
    Row 0 is what the formulas give for ID 0: ``(u_l, 0)`` for every pattern
    except the fan-shape, whose theta(0) = 180 deg puts it at ``(u_l - 2L, 0)``.

    Parameters
    ----------
    name : str
        One of :data:`PATTERN_NAMES` or :data:`GENERIC_NAMES` (with ``k``).
    n : int
        Number of robots (>= 1).
    d_u : float
        The uniform interval (> 0); :func:`interval_for_span` turns a span into it.
    u_l : float
        The leader's u-coordinate (its distance from the common origin, Sec. 2.1).
    **params
        The pattern's parameters (:func:`pattern_info`): ``alpha_star`` (wedge, degrees),
        ``m`` (arc, fan-shape), ``k``, ``rotation``, and the readings ``radius``,
        ``center``, ``index``, ``noline`` (docs/decisions.md).

    Returns
    -------
    numpy.ndarray of shape (n, 2)

    Raises
    ------
    UsageError
        An unknown name or parameter, a bad value, or a formula undefined for these
        arguments (e.g. ``polygon`` with ``k=2``: Table 1's k_m is 0/0 at ID 0).

    Examples
    --------
    >>> target_points("wedge", 3, 1.0, alpha_star=30).round(6).tolist()
    [[0.0, 0.0], [-0.866025, -0.5], [-0.866025, 0.5]]
    >>> target_points("vertical-line", 3, 2.0, u_l=5.0).tolist()
    [[5.0, 0.0], [3.0, 0.0], [7.0, 0.0]]
    >>> target_points("circle", 4, 1.0).round(6).tolist()   # radius 4/(2 pi)
    [[0.0, 0.0], [-0.63662, -0.63662], [-0.63662, 0.63662], [-1.27324, 0.0]]
    """
    _check_name(name)
    n = _check_n(n)
    d_u = _check_real("d_u", d_u)
    if d_u <= 0:
        raise UsageError(f"d_u={d_u!r} must be > 0", fix="give the uniform interval, e.g. d_u=1.0")
    u_l = _check_real("u_l", u_l)
    if _PATTERNS[name][0] == "multi":
        offs = multi_line_offsets(name, n, **params)
        return np.array([(u_l - a * d_u, b * d_u) for a, b in offs], dtype=float).reshape(n, 2)
    return np.array([target_of(name, i, n, d_u, u_l, **params) for i in range(n)], dtype=float).reshape(n, 2)


def target_of(name: str, i: int, n: int, d_u: float, u_l: float = 0.0, **params) -> tuple[float, float]:
    """The target ``f_i`` of the robot with ID ``i`` in a team of ``n`` (what a robot computes for
    itself, 003 Algs. 2-3): row ``i`` of :func:`target_points` for ``i < n``, and the same formulas
    for an ID >= n (Alg. 1's printed numbering can hand out IDs up to ``2 (n - 1)``).

    >>> target_of("two-row", 3, 4, 1.0), target_of("two-row", 5, 4, 1.0)
    ((-1.0, -1.0), (-2.0, -1.0))
    >>> target_of("wedge", 2, 3, 1.0) == tuple(target_points("wedge", 3, 1.0)[2])
    True
    """
    try:
        key = (name, int(i), n, float(d_u), float(u_l), tuple(sorted(params.items())))
        hash(key)
    except (TypeError, ValueError):
        return _target_of(name, i, n, d_u, u_l, **params)
    return _target_of_cached(key)


@functools.lru_cache(maxsize=1 << 16)
def _target_of_cached(key) -> tuple[float, float]:
    """:func:`target_of` remembered: a robot asks for the same targets every step (003's robots
    recompute f_i for every robot they track), and exact angles (Fractions) are slow."""
    name, i, n, d_u, u_l, items = key
    return _target_of(name, i, n, d_u, u_l, **dict(items))


def _target_of(name: str, i: int, n: int, d_u: float, u_l: float = 0.0, **params) -> tuple[float, float]:
    _check_name(name)
    n = _check_n(n)
    if _PATTERNS[name][0] == "multi":
        p = _params(name, params)
        noline = line_count(name, n, reading=p["noline"], **{k: v for k, v in params.items() if k != "noline"})
        a, b = _multi_offset(int(i), noline)
        return (u_l - a * d_u, b * d_u)
    try:
        p = uni_line_parameters(name, n, int(i), d_u, u_l, **params)
    except ZeroDivisionError as exc:
        raise UsageError(f"pattern {name!r} is undefined for n={n} at ID {i}: {exc}",
                         fix="003 Table 1's k_m needs k >= 3 (and index='rational' when n < k)") from None
    c, s = _cos_sin(p["theta_exact"])
    return (c * p["L"] + p["T"], s * p["L"] * p["mark"] + 0.0)   # Alg. 2 lines 4-5 (+0.0: no -0.0)
