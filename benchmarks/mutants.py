"""Seeded faults in copies of the reference implementations (issue 6, mutation benchmark).

Each :class:`Fault` is a mistake a careful reader of the papers could make
while implementing them.  A fault is built as a *copy* of the reference
module (its source is executed again under a new module name, so the copy
has its own classes and functions) in which either a small named
function/method is replaced (``override``), or, where the behaviour lives
inside a long method, one exact source snippet is replaced (``patches``;
the build fails loudly, naming the fault and the snippet, if the reference
no longer contains the snippet exactly once).  ``reference_impl/`` itself is
never edited and the originals are never patched: the copy is the mutant.

A mutant is registered in :mod:`swarmproof.reference_impl.registry` under
its own name (``"song2016~nclb-ignored"``), with the reference's claims, so
the explorer and plain runs use it like any other algorithm.

Every fault names the paper place it breaks (seed file and section / line)
and the properties expected to catch it; each catching property is one the
*reference* holds on the explorer's default scenarios (song2014 violates
``connectivity`` and ``tree_links`` as written, 001 Sec. I, so its faults
are hunted with ``formation`` or ``oscillation`` instead).  Two song2016
faults only show with long steps, so every song2016 fault is hunted over
the speeds :data:`SONG2016_SPEEDS` (each scenario draws its v, inside the
assumption v dt < phi), by both hunters of the benchmark.

Usage::

    from mutants import FAULTS, registered
    with registered(FAULTS) as names:        # registry names of the mutants
        explore(names[0], ["formation"], ...)

References
----------
000_3ad33c5b62f11d5f.txt (song2014): Sec. IV-A (Defs. 4-5), IV-B (Def. 6),
IV-C (Lemma 7, Eq. 8), IV-D.  001_7a4e517b856331bc.txt (song2016): Lemma 7,
Def. 8, Sec. V-A (Def. 9 and the vacancy transform), Sec. V-B (Algorithm 1
line 12, Def. 10), Sec. V-C (NCLB, d_s, the three cases), Sec. VI (timeouts).
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.util
import math
import sys
import types
from dataclasses import dataclass, field
from typing import Callable, Iterator, Sequence

from swarmproof.models.errors import UsageError

__all__ = ["Fault", "FAULTS", "FAULT_NAMES", "MutantBuildError", "build_module", "get_fault",
           "register", "registered", "unregister"]

REFERENCE_MODULES = {
    "song2014": ("swarmproof.reference_impl.song2014.algorithm", "Song2014"),
    "song2016": ("swarmproof.reference_impl.song2016.algorithm", "Song2016"),
}


class MutantBuildError(UsageError):
    """A fault could not be applied to the current reference implementation."""


@dataclass(frozen=True)
class Fault:
    """One seeded fault.

    Attributes
    ----------
    name : str
        Registry name, ``"<reference>~<slug>"``.
    reference : str
        ``"song2014"`` or ``"song2016"``.
    description : str
        One line: what the mutant does differently.
    breaks : str
        The paper place it breaks (seed file and section / line).
    catches : tuple of str
        Explorer properties expected to catch it (the benchmark hunts the first).
    override : callable, optional
        ``override(module)`` replaces names in the copied module.
    patches : tuple of (str, str)
        Exact source snippets ``(old, new)`` of the reference module; each
        ``old`` must occur exactly once.
    options : dict
        Property options passed to the judge (e.g. ``{"radius": 0.05}``).
    params : dict
        Overrides of ``v``, ``omega``, ``dt`` for the scenarios of *both*
        hunters, inside the paper's assumptions.  Empty: the algorithm's defaults.
    speeds : tuple of float
        When not empty, every scenario of *both* hunters draws its ``v`` from
        these (the explorer with ``explore(speeds=...)``, Monte Carlo
        uniformly); all inside the paper's assumptions.
    equivalent : str
        Not empty for a fault shown *equivalent* with respect to every checked
        property (it changes the runs, never a verdict): why, and where the
        evidence is.  The benchmark still hunts it and reports the share found
        both with and without it.
    """

    name: str
    reference: str
    description: str
    breaks: str
    catches: tuple[str, ...]
    override: Callable[[types.ModuleType], None] | None = None
    patches: tuple[tuple[str, str], ...] = ()
    options: dict = field(default_factory=dict)
    params: dict = field(default_factory=dict)
    speeds: tuple[float, ...] = ()
    equivalent: str = ""

    @property
    def target(self) -> str:
        """The property the benchmark hunts (the first of ``catches``)."""
        return self.catches[0]

    @property
    def module_name(self) -> str:
        slug = self.name.replace("~", "__").replace("-", "_")
        return f"swarmproof_mutant_{slug}"


# ---------------------------------------------------------------------------
# building a copy
# ---------------------------------------------------------------------------

def _apply_patches(fault: Fault, source: str, origin: str) -> str:
    for old, new in fault.patches:
        count = source.count(old)
        if count != 1:
            raise MutantBuildError(
                f"fault={fault.name!r}: the snippet {old!r} occurs {count} times in {origin} (expected 1)",
                fix="the reference implementation changed; update the fault's patch in benchmarks/mutants.py")
        source = source.replace(old, new)
    return source


def build_module(fault: Fault) -> types.ModuleType:
    """Execute a copy of the fault's reference module with the fault applied.

    The copy is registered in ``sys.modules`` under :attr:`Fault.module_name`
    (so the registry can import it) and its algorithm class is renamed to
    the fault's name.  Rebuilding replaces an earlier copy.

    Raises
    ------
    MutantBuildError
        When a patch snippet is not found exactly once.
    """
    if fault.reference not in REFERENCE_MODULES:
        raise MutantBuildError(f"fault={fault.name!r}: reference={fault.reference!r} is not known",
                               fix=f"use one of {sorted(REFERENCE_MODULES)!r}")
    modname, cls = REFERENCE_MODULES[fault.reference]
    spec = importlib.util.find_spec(modname)
    origin = spec.origin
    with open(origin, encoding="utf-8") as fh:
        source = fh.read()
    source = _apply_patches(fault, source, origin)
    mod = types.ModuleType(fault.module_name, f"mutant {fault.name}: {fault.description}")
    mod.__file__ = origin
    mod.__package__ = modname.rpartition(".")[0]   # relative imports resolve as in the reference
    sys.modules[fault.module_name] = mod           # dataclasses look the module up while executing
    try:
        exec(compile(source, f"{origin} [{fault.name}]", "exec"), mod.__dict__)
        if fault.override is not None:
            fault.override(mod)
    except BaseException:
        sys.modules.pop(fault.module_name, None)
        raise
    algo_cls = getattr(mod, cls)
    algo_cls.name = fault.name
    # the copy keeps its reference's claims and premise monitors (class attributes), but gets
    # no rows of its own in swarmproof verify
    algo_cls.verify = None
    return mod


def register(fault: Fault) -> str:
    """Build the mutant and register it (with the reference's claims); returns its name."""
    from swarmproof.reference_impl import registry

    build_module(fault)
    registry.ALGORITHMS[fault.name] = f"{fault.module_name}:{REFERENCE_MODULES[fault.reference][1]}"
    return fault.name


def unregister(fault: Fault) -> None:
    """Remove the mutant from the registry and ``sys.modules``."""
    from swarmproof.reference_impl import registry

    registry.ALGORITHMS.pop(fault.name, None)
    sys.modules.pop(fault.module_name, None)


@contextlib.contextmanager
def registered(faults: Sequence[Fault]) -> Iterator[list[str]]:
    """Register ``faults`` for the duration of a ``with`` block; yields their names."""
    done: list[Fault] = []
    try:
        for f in faults:
            register(f)
            done.append(f)
        yield [f.name for f in done]
    finally:
        for f in done:
            unregister(f)


# ---------------------------------------------------------------------------
# the overrides (each replaces one small named function or method in the copy)
# ---------------------------------------------------------------------------

def _replace_controller_method(mod, class_name: str, method: str, make: Callable) -> None:
    """Replace ``class_name`` in the copy by a subclass whose ``method`` is ``make(base)``
    (the algorithm's ``controller()`` builds the class by its module-level name)."""
    base = getattr(mod, class_name)
    sub = type(class_name, (base,), {"__slots__": (), method: make(base)})
    setattr(mod, class_name, sub)


def _s14_def5_length_reversed(mod) -> None:
    # Def. 5 item 2 read backwards: among authorities of the same root the LONGER one is higher.
    def authority_key(authority):
        return (authority[0], len(authority), authority[-1])
    mod.authority_key = authority_key


def _s14_no_forced_cell(mod) -> None:
    # Sec. IV-B-2 without the forced cell: a descendant's matching may give its
    # parent another edge than the inverse of its own (and the parent's row is free).
    original = mod.match_positions

    def match_positions(neighbor_xy, edge_xy, forced=None):
        return original(neighbor_xy, edge_xy, None)
    mod.match_positions = match_positions


def _s14_no_eq8_turn(mod) -> None:
    # Sec. IV-C / Eq. 8 skipped: at the destination the descendant does not turn to
    # the heading of the edge, so its own matching is made in a rotated frame.
    original = mod.descendant_motion

    def descendant_motion(parent_pose, edge_pose, params, arrive_tol, heading_tol=1e-9):
        turn, forward, dest = original(parent_pose, edge_pose, params, arrive_tol, heading_tol)
        if math.hypot(dest[0], dest[1]) <= arrive_tol:
            return 0.0, 0.0, dest
        return turn, forward, dest
    mod.descendant_motion = descendant_motion


def _s14_disperse_toward_parent(mod) -> None:
    # Sec. IV-D read backwards: an unmatched robot drives TOWARD its parent for 2 phi / v.
    def make(base):
        def _start_dispersal(self, step, parent_xy):
            return base._start_dispersal(self, step, (-float(parent_xy[0]), -float(parent_xy[1])))
        return _start_dispersal
    _replace_controller_method(mod, "Song2014Controller", "_start_dispersal", make)


def _s16_range_phi(mod) -> None:
    # Lemma 7 / Def. 8 with the bounded range radius phi instead of phi - v dt.
    def bounded_range_radius(phi, v, dt):
        return phi
    mod.bounded_range_radius = bounded_range_radius


def _s16_nclb_ignored(mod) -> None:
    # Sec. V-C without NCLB: a moving robot heads straight for its goal, ignoring
    # the bounded ranges of its children (the safe region is the whole plane).
    def closest_point_in_discs(goal, centers, radius):
        return (float(goal[0]), float(goal[1]))

    def farthest_point_toward(goal, centers, radius):
        return (float(goal[0]), float(goal[1]))

    def in_discs(x, y, centers, radius, tol=0.0):
        return True
    mod.closest_point_in_discs = closest_point_in_discs
    mod.farthest_point_toward = farthest_point_toward
    mod.in_discs = in_discs


def _s16_cfg(**changes) -> Callable:
    # A value of Song2016Config replaced in every controller (the assumptions the
    # algorithm declares still see the paper's value: the mistake is in the code).
    def override(mod) -> None:
        original = mod.Song2016.controller

        def controller(self, robot_id, params, lattice, rng):
            ctl = original(self, robot_id, params, lattice, rng)
            ctl.cfg = dataclasses.replace(ctl.cfg, **changes)
            return ctl
        mod.Song2016.controller = controller
    return override


def _s16_vacancy_as_printed(mod) -> None:
    # Sec. V-A, the vacancy transform exactly as printed: M^(s) M_s^(i) [0 0 1]^T
    # (factors swapped; docs/decisions.md "Vacancy in the observer's frame").
    def vacancy_in_observer_frame(observed_owner, vacancy):
        ox, oy, oth = float(observed_owner[0]), float(observed_owner[1]), float(observed_owner[2])
        c, s = math.cos(vacancy.theta), math.sin(vacancy.theta)
        return (vacancy.x + c * ox - s * oy, vacancy.y + s * ox + c * oy,
                mod.wrap_angle(oth + vacancy.theta))
    mod.vacancy_in_observer_frame = vacancy_in_observer_frame


def _s16_unstable_fills_vacancy(mod) -> None:
    # Def. 9 without its parenthesis: ANY robot at p_hat fills the vacancy, an unstable one too.
    def make(base):
        def _my_vacancy(self, pose_of, messages):
            if not self.stable:
                return None
            xy = tuple((pose_of[i][0], pose_of[i][1]) for i, m in messages if i in pose_of)
            vac = mod.vacancies(self._out_edges[self.role], xy, self.cfg.vacancy_tolerance)
            return vac[0] if vac else None
        return _my_vacancy
    _replace_controller_method(mod, "Song2016Controller", "_my_vacancy", make)


# ---------------------------------------------------------------------------
# the faults
# ---------------------------------------------------------------------------

#: The speeds v every song2016 scenario draws from (both hunters): the paper's default 0.05
#: (001 Sec. VI) and longer steps up to 1.1, all inside v dt < phi on every bundled lattice
#: (phi >= 1.2); the reference song2016 held all eight explorer properties over 300 scenarios
#: drawn from them; until its case-3 fix (2026-11-24, docs/song2016.md) it broke tree links on
#: rare starts at v >= 0.4, so the benchmark counts a violation only where the reference passes
#: (bench_mutations.reference_fails_too).
SONG2016_SPEEDS: tuple[float, ...] = (0.05, 0.2, 0.4, 0.8, 1.1)

FAULTS: tuple[Fault, ...] = (
    Fault("song2014~def5-longer-wins", "song2014",
          "Def. 5 item 2 reversed: of two authorities with the same root the longer one is higher",
          "000 Sec. IV-A-1, Definition 5 item 2", ("oscillation", "formation"),
          override=_s14_def5_length_reversed),
    Fault("song2014~no-forced-cell", "song2014",
          "a descendant's matching does not force its parent onto the inverse edge",
          "000 Sec. IV-B-2 (forced row and column of the weight matrix)", ("formation", "oscillation"),
          override=_s14_no_forced_cell,
          equivalent=("the parent's row is never read (a parent discards its child's message, 000 "
                      "Sec. IV-A-2) and at rest the parent sits on the inverse edge's cell, so the "
                      "unforced optimal matching equals the forced one (triangle inequality): same "
                      "static states; 540 paired runs, matchings differ in 17-23% of moving steps, "
                      "0 of 64,572 at rest, every verdict of formation, deadlock, termination and "
                      "oscillation the same (docs/explorer.md, \"Mutation benchmark\")")),
    Fault("song2014~no-eq8-turn", "song2014",
          "a descendant at its destination does not turn to the heading of Eq. 8",
          "000 Sec. IV-C, Eq. 8", ("formation",),
          override=_s14_no_eq8_turn),
    Fault("song2014~disperse-toward-parent", "song2014",
          "an unmatched robot drives toward its parent instead of directly away",
          "000 Sec. IV-D", ("oscillation", "formation"),
          override=_s14_disperse_toward_parent),
    Fault("song2016~range-phi", "song2016",
          "bounded range radius phi instead of phi - v dt (safe region and d_s too large)",
          "001 Lemma 7, Definition 8, Sec. V-C", ("premises", "tree_links", "connectivity"),
          override=_s16_range_phi, speeds=SONG2016_SPEEDS),
    Fault("song2016~nclb-ignored", "song2016",
          "a moving parent/relocate robot goes straight to its goal, ignoring its children's bounded ranges",
          "001 Sec. V-C (No Child Left Behind, safe region)", ("tree_links", "connectivity"),
          override=_s16_nclb_ignored, speeds=SONG2016_SPEEDS),
    Fault("song2016~own-id-check-removed", "song2016",
          "Algorithm 1 line 12 removed: information whose path holds my own ID is accepted (rumors)",
          "001 Sec. V-B, Algorithm 1 line 12 (the rumor problem)", ("deadlock", "formation"),
          patches=(("in_root_path = my_id in m.path_from_root", "in_root_path = False"),
                   ("in_reloc_path = my_id in m.path_from_relocate", "in_reloc_path = False")),
          speeds=SONG2016_SPEEDS),
    Fault("song2016~comm-timeout-1", "song2016",
          "communication timeout of 1 step in the controllers (the paper: n, Sec. VI; >= n - 1 hops)",
          "001 Def. 10, Lemma 12, Sec. VI", ("formation", "deadlock"),
          override=_s16_cfg(communication_timeout=1),
          speeds=SONG2016_SPEEDS),
    Fault("song2016~move-timeout-0", "song2016",
          "movement timeout of 0 steps: a new mover moves before its neighbors have taken it as parent",
          "001 Sec. V-C, Sec. VI (movement timeout)", ("connectivity", "tree_links"),
          override=_s16_cfg(movement_timeout=0), speeds=SONG2016_SPEEDS),
    Fault("song2016~root-parent-case-dropped", "song2016",
          "the relocate robot always heads for its parent, also when the parent is the root",
          "001 Sec. V-C case 2 (\"unless its parent is the root ... toward the vacancy\")",
          ("formation", "deadlock"),
          patches=(("if parent == msg.root_id:", "if False:  # mutant: root case dropped"),),
          speeds=SONG2016_SPEEDS),
    Fault("song2016~arrival-ignores-heading", "song2016",
          "the relocate robot turns stable on reaching the vacancy's position, whatever its heading",
          "001 Sec. V-A (\"after it reaches this pose\"), footnote 2", ("formation", "deadlock"),
          patches=(("and abs(wrap_angle(vth)) <= cfg.heading_epsilon):", "):  # mutant: heading ignored"),),
          speeds=SONG2016_SPEEDS),
    Fault("song2016~vacancy-as-printed", "song2016",
          "vacancy moved into the observer's frame by the printed product M^(s) M_s^(i) (factors swapped)",
          "001 Sec. V-A (equations after Def. 9)", ("oscillation", "tree_links"),
          override=_s16_vacancy_as_printed,
          speeds=SONG2016_SPEEDS),
    Fault("song2016~unstable-fills-vacancy", "song2016",
          "an unstable robot at a vacancy's pose fills it (Def. 9 says it does not)",
          "001 Sec. V-A, Definition 9 (parenthesis)", ("oscillation", "deadlock"),
          override=_s16_unstable_fills_vacancy,
          speeds=SONG2016_SPEEDS),
)

FAULT_NAMES: tuple[str, ...] = tuple(f.name for f in FAULTS)


def get_fault(name: str) -> Fault:
    """The fault called ``name``; :class:`UsageError` listing the valid names otherwise."""
    for f in FAULTS:
        if f.name == name:
            return f
    raise UsageError(f"fault={name!r} is not known", fix=f"use some of {list(FAULT_NAMES)!r}")
