"""Initial configurations: random connected starts from a seed, and files.

:func:`random_connected` draws what 001 Sec. VI describes ("randomly
generated but with communication graph connected"): n robots with a
minimum separation whose communication graph at range phi (neighbors
strictly closer than phi) is connected.  The paper does not say how; we
grow the configuration (docs/decisions.md, "Simulation engine"): the first
robot at the origin (or the centre of the ``spread`` box); each next robot
at a uniformly random bearing and a distance uniform in
``[min_separation, range)`` from a uniformly chosen robot already placed,
kept if it is at least ``min_separation`` from every robot (and inside the
box, if any), else redrawn (at most ``max_tries`` draws per robot).
Headings are uniform in ``[-pi, pi)``; IDs are a random permutation of
``0..n-1``.  Everything is drawn from the one generator given, so the same
seed gives the same configuration.

File format ``swarmproof-initial/1`` (YAML or JSON, same keys)::

    format: swarmproof-initial/1
    angle_unit: deg          # optional: deg (default) or rad
    robots:
      - {id: 3, pose: [0.0, 0.0, 90.0]}
      - {id: 1, pose: [0.8, 0.0, 0.0]}

Every ``x``, ``y`` and ``theta`` is a finite number of size at most 1e6 (the lattice files'
bound, docs/file-format.md "Limits"), and no two robots stand within 1e-9 of each other.

References
----------
001_7a4e517b856331bc.txt (Song & O'Kane 2016), Sec. III (connected start),
Sec. VI (random connected initial configurations).

Examples
--------
>>> c = random_connected(5, 7, range=1.0, min_separation=0.3)
>>> c.n, sorted(c.ids.tolist())
(5, [0, 1, 2, 3, 4])
>>> c == random_connected(5, 7, range=1.0, min_separation=0.3)
True
>>> from swarmproof.models.sensing import is_connected
>>> is_connected(c.poses[:, :2], 1.0)
True
"""

from __future__ import annotations

import builtins
import math
import os

import numpy as np

from swarmproof.models.doclines import field_name, line_of, num_text, parse_document
from swarmproof.models.errors import InputFileError, UsageError, check_positive, check_type
from swarmproof.models.fileio import atomic_write_text, dumps_json
from swarmproof.models.lattice_io import MAX_MAGNITUDE
from swarmproof.models.sensing import is_connected
from swarmproof.models.trace import InitialConfiguration

__all__ = ["InitialConfiguration", "random_connected", "random_uniform", "from_file", "to_file", "loads", "dumps",
           "INITIAL_FORMAT"]

INITIAL_FORMAT = "swarmproof-initial/1"


def _generator(rng_or_seed) -> np.random.Generator:
    if isinstance(rng_or_seed, np.random.Generator):
        return rng_or_seed
    if isinstance(rng_or_seed, (int, np.integer)) and not isinstance(rng_or_seed, bool):
        if rng_or_seed < 0:
            raise UsageError(f"seed={rng_or_seed!r} must be >= 0")
        return np.random.default_rng(int(rng_or_seed))
    raise UsageError(f"rng_or_seed={rng_or_seed!r} must be a non-negative int seed or a "
                     "numpy.random.Generator", fix="pass an explicit seed")


def random_uniform(n: int, seed: int, *, side: float, min_separation: float = 0.0) -> InitialConfiguration:
    """``n`` robots uniformly at random in the square ``[0, side]^2`` (002 Sec. V-A: "placed
    randomly and uniformly in the working plane"), at least ``min_separation`` apart (rejection),
    headings uniform, IDs ``0..n-1``; seeded (its own stream of ``seed``).  Not necessarily
    connected: for algorithms whose robots all hear each other.

    >>> s = random_uniform(20, 0, side=15.0, min_separation=0.14)
    >>> s.n, bool((s.poses[:, :2] >= 0).all() and (s.poses[:, :2] <= 15).all())
    (20, True)
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise UsageError(f"n={n!r} must be an integer >= 1")
    if not (isinstance(side, (int, float)) and math.isfinite(side) and side > 0):
        raise UsageError(f"side={side!r} must be a finite number > 0")
    rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(2002,)))
    pts: list = []
    tries = 0
    while len(pts) < n:
        tries += 1
        if tries > 1000 * n:
            raise UsageError(f"cannot place n={n} robots {min_separation} apart in a square of side={side}",
                             fix="give a larger side or fewer robots")
        p = rng.uniform(0.0, side, size=2)
        if all(math.hypot(*(p - q)) >= min_separation for q in pts):
            pts.append(p)
    head = rng.uniform(-np.pi, np.pi, size=n)
    return InitialConfiguration(list(range(n)), np.column_stack((np.array(pts), head)))


def random_connected(n: int, rng_or_seed, *, range: float, min_separation: float | None = None,
                     spread: float | None = None, max_tries: int = 1000) -> InitialConfiguration:
    """A random initial configuration whose communication graph is connected.

    Parameters
    ----------
    n : int
        Number of robots, >= 1.
    rng_or_seed : int or numpy.random.Generator
        The only source of randomness.
    range : float
        phi; neighbors are strictly closer than it.
    min_separation : float, optional
        Smallest distance between two robots, in ``[0, range)``; default
        ``range / 4``.
    spread : float, optional
        If given, every robot lies in the square ``[0, spread]^2``.
    max_tries : int
        Draws per robot before giving up.

    Returns
    -------
    InitialConfiguration

    Raises
    ------
    UsageError
        Bad arguments, or a robot could not be placed in ``max_tries`` draws
        (names the robot and says what to relax).
    """
    check_type("n", n, (int, np.integer))
    if n < 1:
        raise UsageError(f"n={n!r} must be >= 1", fix="ask for at least one robot")
    phi = check_positive("range", range)
    sep = phi / 4 if min_separation is None else float(min_separation)
    if not (math.isfinite(sep) and 0 <= sep < phi):
        raise UsageError(f"min_separation={min_separation!r} must be in [0, range={phi!r})",
                         fix="robots closer than the range are needed for a connected start")
    if spread is not None:
        spread = check_positive("spread", spread)
    check_type("max_tries", max_tries, (int, np.integer))
    rng = _generator(rng_or_seed)
    xy = np.zeros((n, 2))
    if spread is not None:
        xy[0] = spread / 2
    for k in np.arange(1, n):
        for _ in np.arange(max_tries):
            a = int(rng.integers(k))
            r = rng.uniform(sep, phi)
            ang = rng.uniform(-math.pi, math.pi)
            cand = xy[a] + r * np.array([math.cos(ang), math.sin(ang)])
            d_anchor = cand - xy[a]
            if not math.hypot(d_anchor[0], d_anchor[1]) < phi:
                continue
            if spread is not None and not (0 <= cand[0] <= spread and 0 <= cand[1] <= spread):
                continue
            d = xy[:k] - cand
            if sep > 0 and np.min(np.hypot(d[:, 0], d[:, 1])) < sep:
                continue
            xy[k] = cand
            break
        else:
            raise UsageError(
                f"could not place robot {int(k)} of n={n} in max_tries={max_tries} draws "
                f"(range={phi!r}, min_separation={sep!r}, spread={spread!r})",
                fix="lower min_separation, enlarge spread, or raise max_tries")
    if not is_connected(xy, phi):  # pragma: no cover - guaranteed by construction
        raise UsageError("internal: generated configuration is not connected")
    theta = rng.uniform(-math.pi, math.pi, n)
    ids = rng.permutation(n)
    return InitialConfiguration(ids, np.column_stack((xy, theta)))


# ----------------------------------------------------------------------------
# Files
# ----------------------------------------------------------------------------

def random_grid_connected(n: int, rng_or_seed, *, range: float, spacing: float) -> InitialConfiguration:
    """A random connected start on grid cells (``motion="grid"`` robots), heading 0.

    Robot k > 0 takes a free cell within ``range`` (strictly: the start is
    connected under either neighbor rule) of a robot placed before it,
    chosen uniformly among such cells of a uniformly drawn earlier robot.

    >>> c = random_grid_connected(6, 0, range=0.6, spacing=0.2)
    >>> c.n, bool((abs(c.poses[:, :2] / 0.2 - (c.poses[:, :2] / 0.2).round()) < 1e-9).all())
    (6, True)
    """
    check_type("n", n, (int, np.integer))
    if n < 1:
        raise UsageError(f"n={n!r} must be >= 1", fix="ask for at least one robot")
    phi = check_positive("range", range)
    step = check_positive("spacing", spacing)
    reach = int(math.floor(phi / step))
    offsets = [(dx, dy) for dx in builtins.range(-reach, reach + 1) for dy in builtins.range(-reach, reach + 1)
               if (dx, dy) != (0, 0) and math.hypot(dx, dy) * step < phi]
    if not offsets:
        raise UsageError(f"range={phi!r} is not above spacing={step!r}: no two grid cells are neighbors",
                         fix="give a range larger than the grid spacing")
    rng = _generator(rng_or_seed)
    cells = [(0, 0)]
    taken = {(0, 0)}
    while len(cells) < n:
        base = cells[int(rng.integers(len(cells)))]
        dx, dy = offsets[int(rng.integers(len(offsets)))]
        c = (base[0] + dx, base[1] + dy)
        if c not in taken:
            cells.append(c)
            taken.add(c)
    poses = np.array([[cx * step, cy * step, 0.0] for cx, cy in cells], dtype=float)
    return InitialConfiguration(list(builtins.range(n)), poses)


def dumps(config: InitialConfiguration, fmt: str = "yaml", angle_unit: str = "deg") -> str:
    """The ``swarmproof-initial/1`` text of ``config`` (``fmt`` "yaml" or "json").

    ``angle_unit="rad"`` round-trips bit for bit; degrees may change the last bit
    of theta.

    >>> print(dumps(InitialConfiguration([2], [[0.5, 0, math.pi / 2]])), end="")
    format: swarmproof-initial/1
    angle_unit: deg
    robots:
    - {id: 2, pose: [0.5, 0.0, 90.0]}
    """
    if angle_unit not in ("deg", "rad"):
        raise UsageError(f"angle_unit={angle_unit!r} must be 'deg' or 'rad'")
    doc = {"format": INITIAL_FORMAT, "angle_unit": angle_unit, **config.as_dict(angle_unit)}
    if fmt == "json":
        return dumps_json(doc)
    if fmt != "yaml":
        raise UsageError(f"fmt={fmt!r} must be 'yaml' or 'json'")
    lines = [f"format: {INITIAL_FORMAT}", f"angle_unit: {angle_unit}", "robots:"]
    for r in doc["robots"]:
        x, y, th = (repr(float(v)) for v in r["pose"])
        lines.append(f"- {{id: {r['id']}, pose: [{x}, {y}, {th}]}}")
    return "\n".join(lines) + "\n"


def to_file(config: InitialConfiguration, path, angle_unit: str = "deg") -> str:
    """Write ``config`` atomically; ``.json`` gives JSON, anything else YAML."""
    path = os.fspath(path)
    fmt = "json" if path.lower().endswith(".json") else "yaml"
    return atomic_write_text(path, dumps(config, fmt, angle_unit))


#: Two robots of an initial file closer than this stand on one spot (an input error).
SAME_POINT_TOL = 1e-9


def loads(text: str, fmt: str = "yaml", source: str = "<string>") -> InitialConfiguration:
    """Parse a ``swarmproof-initial/1`` document.

    Raises
    ------
    InputFileError
        Naming the file, line and field (e.g. ``robots[2].pose[1]``) and a fix.

    Examples
    --------
    >>> loads("format: swarmproof-initial/1\\nrobots:\\n  - {id: 1, pose: [0, 0]}\\n", source="s.yaml")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.InputFileError: s.yaml:3: field 'robots[0].pose': robots[0].pose=[0, 0] must be [x, y, theta]; fix: give three numbers
    """
    data, lines = parse_document(text, fmt, source)

    def err(path, message, fix=None):
        return InputFileError(message, file=source, line=line_of(lines, path),
                              field=field_name(path) or None, fix=fix)

    if not isinstance(data, dict):
        raise err((), f"top level is {type(data).__name__}, expected a mapping",
                  f"write `format: {INITIAL_FORMAT}` and a `robots` list")
    if data.get("format") != INITIAL_FORMAT:
        raise err(("format",), f"format={data.get('format')!r} is not {INITIAL_FORMAT!r}",
                  f"write `format: {INITIAL_FORMAT}`")
    unknown = sorted(set(data) - {"format", "angle_unit", "robots"})
    if unknown:
        raise err((unknown[0],), f"unknown key {unknown[0]!r}", "keys are format, angle_unit, robots")
    unit = data.get("angle_unit", "deg")
    if unit not in ("deg", "rad"):
        raise err(("angle_unit",), f"angle_unit={unit!r} is not a known unit", "use 'deg' or 'rad'")
    robots = data.get("robots")
    if not isinstance(robots, list) or not robots:
        raise err(("robots",), f"robots={robots!r} must be a non-empty list",
                  "list robots as {id: ..., pose: [x, y, theta]}")
    ids, poses = [], []
    for k, r in enumerate(robots):
        if not isinstance(r, dict):
            raise err(("robots", k), f"robots[{k}]={r!r} must be a mapping", "write {id: ..., pose: [x, y, theta]}")
        extra = sorted(set(r) - {"id", "pose"})
        if extra:
            raise err(("robots", k, extra[0]), f"unknown key {extra[0]!r}", "keys are id and pose")
        rid = r.get("id")
        if isinstance(rid, bool) or not isinstance(rid, int):
            raise err(("robots", k, "id"), f"robots[{k}].id={rid!r} must be an integer", "give a whole-number ID")
        pose = r.get("pose")
        if not isinstance(pose, list) or len(pose) != 3:
            raise err(("robots", k, "pose"), f"robots[{k}].pose={pose!r} must be [x, y, theta]",
                      "give three numbers")
        vals = []
        for j, v in enumerate(pose):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise err(("robots", k, "pose", j), f"robots[{k}].pose[{j}]={v!r} must be a finite number",
                          "write a plain number")
            if not abs(v) <= MAX_MAGNITUDE:
                raise err(("robots", k, "pose", j),
                          f"robots[{k}].pose[{j}]={num_text(v)} is beyond the bound |{('x', 'y', 'theta')[j]}| <= 1e6",
                          "reduce the angle modulo 360 deg (2 pi rad)" if j == 2 else
                          "scale the start (and the range) by one factor, e.g. metres instead of micrometres, "
                          "so that every coordinate is at most 1e6 (far beyond it the robots' squared "
                          "distances overflow)")
            vals.append(float(v))
        if unit == "deg":
            vals[2] = math.radians(vals[2])
        ids.append(rid)
        poses.append(vals)
    same = _first_same_point(poses)
    if same is not None:
        j, k = same
        raise err(("robots", k, "pose"),
                  f"robots[{k}] (id={ids[k]!r}) at ({poses[k][0]!r}, {poses[k][1]!r}) is on the same point as "
                  f"robots[{j}] (id={ids[j]!r}): two robots cannot stand on one spot",
                  "move one of them")
    return InitialConfiguration(np.array(ids, dtype=np.int64), np.array(poses))


def _first_same_point(poses: list) -> tuple[int, int] | None:
    """The first pair ``(j, k)``, ``j < k``, in file order (smallest ``k``, then ``j``) of robots
    within :data:`SAME_POINT_TOL` of each other, or None.  A k-d tree: linear-ish in the robots
    (comparing every pair took a minute for 20,000 robots)."""
    from scipy.spatial import cKDTree

    if len(poses) < 2:
        return None
    pairs = cKDTree(np.asarray(poses, dtype=float)[:, :2]).query_pairs(SAME_POINT_TOL, p=2.0)
    return min(((min(a, b), max(a, b)) for a, b in pairs), key=lambda jk: (jk[1], jk[0]), default=None)


def from_file(path) -> InitialConfiguration:
    """Read a ``swarmproof-initial/1`` file (``.json`` as JSON, anything else as YAML)."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise InputFileError("is a directory", file=path, fix="give a .yaml or .json file")
    try:
        with open(path, encoding="utf-8-sig") as f:
            text = f.read()
    except FileNotFoundError:
        raise InputFileError("no such file", file=path, fix="check the path") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"cannot read the file ({exc})", file=path,
                             fix="give a readable UTF-8 file") from None
    if not text.strip():
        raise InputFileError("the file is empty", file=path, line=1,
                             fix=f"write a {INITIAL_FORMAT} document")
    return loads(text, "json" if path.lower().endswith(".json") else "yaml", path)
