"""The z3 proof suite for the safety lemmas (issue 5; DESIGN.md sections 3 and 4).

One small encoding per lemma, named after the mathematics, its variables
indexed by time step (``p_i_0`` is ``p_i(t)``, ``p_i_1`` is ``p_i(t+dt)``).
Validity is shown by asserting the negation of the conclusion and getting
``unsat``.  Every lemma is checked in three steps (:func:`prove`):

1. its premises are satisfiable (else the proof would be vacuous: reported
   ``inconclusive``);
2. premises and ``Not(conclusion)`` are ``unsat`` (``proved``); ``sat`` gives a
   concrete counterexample as numbers; ``unknown`` or a timeout is
   ``inconclusive``, never proved;
3. a negative control, the same lemma with one premise weakened, must be
   refuted with a concrete counterexample; a control that also "proves"
   suggests an encoding that cannot fail, and the lemma is then reported
   ``inconclusive`` ("negative control not refuted");
4. vacuity controls (:func:`vacuity_controls`): each premise dropped in turn
   must give a counterexample for at least one of them, and the conclusion
   must not survive dropping them all (else: tautological, ``inconclusive``).

Each lemma has a ``kind``: ``"paper lemma"`` when it encodes a paper's
numbered result with its premises, else ``"auxiliary"``; ``not_proved``
lists what it does not cover that a reader could take it to.

Normalisation (DESIGN.md section 4, measured): every geometric lemma is
stated with the centre of the disc it reasons about at the origin
(translation invariance), with ``phi = 1`` and ``s = v*dt/phi`` as one
variable (scale invariance).  The invariances are lemmas of their own
(``translation_invariance``, ``rotation_invariance``, ``scale_invariance``),
proved by the same procedure; docs/proofs.md says why they make the
normalised statements equivalent to the general ones.  Distances are
compared through their squares (no distance variables, no quantifiers).

Examples
--------
>>> r = prove(LEMMAS["relocate_stays_in_range"])
>>> r.status, r.premises_satisfiable, r.negative_control["status"]
('proved', True, 'counterexample')
>>> sorted(LEMMAS)[:3]
['bounded_range', 'bounded_range_strict', 'gather_follower_link_kept']

Where the lemmas come from: the types and the normalisation lemmas are in
:mod:`swarmproof.invariants.lemmas`; each paper's lemmas are in its package and reach this
module through the algorithm registry (:func:`swarmproof.reference_impl.registry.lemma_sets`),
so this prover knows no paper.

References
----------
000_3ad33c5b62f11d5f.txt Lemma 7, Sec. IV-C, Fig. 6;
001_7a4e517b856331bc.txt Lemma 7, Def. 8, Sec. V-C, Lemma 11.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable, Iterable, Sequence

import numpy as np
import z3

from swarmproof.invariants.lemmas import Encoding, Lemma, dist2, lemma_solver, point as _pt
from swarmproof.invariants.normalisation import NORMALISATION_LEMMAS
from swarmproof.models.errors import UsageError, check_positive, did_you_mean
from swarmproof.reference_impl.registry import lemma_sets

__all__ = [
    "Encoding",
    "Lemma",
    "LemmaResult",
    "LEMMAS",
    "EXTRA_LEMMAS",
    "prove",
    "run_suite",
    "lookup",
    "model_to_numbers",
    "confirm_trees",
    "case_families",
    "kernel_oracle_check",
    "vacuity_controls",
    "solve",
    "premise_names",
    "Budget",
    "check_rlimit",
    "DEFAULT_RLIMIT",
    "DEFAULT_TIMEOUT_S",
]

#: The outer wall-clock cap per lemma (seconds).  It decides nothing on a machine working as
#: expected: the rlimit budget does (z3 counts its work deterministically).
DEFAULT_TIMEOUT_S = 300.0
#: z3's work budget per lemma when the lemma sets none (``Lemma.rlimit``): ten times what the
#: costliest bundled lemma uses with z3 5.4 (wang2020_separation_equal_speeds, about 2e7 units,
#: about 6 s here); docs/proofs.md "Budgets".
DEFAULT_RLIMIT = 200_000_000
#: z3 takes the resource limit as an unsigned 32-bit count.
MAX_RLIMIT = 2**32 - 1
#: Longest accepted wall-clock cap (one day): z3 takes its timeout as 32-bit milliseconds.
MAX_TIMEOUT_S = 86400.0
#: z3's work budget per tree case of :func:`confirm_trees` and per check of
#: :func:`kernel_oracle_check` (each far below it: docs/proofs.md "Budgets").
CASE_RLIMIT = 50_000_000


@dataclass
class LemmaResult:
    """The outcome of :func:`prove` (DESIGN.md section 2, ``prove`` JSON)."""

    id: str
    statement: str
    cites: list
    status: str  # proved | counterexample | inconclusive
    seconds: float
    premises_satisfiable: bool | None
    negative_control: dict
    counterexample: dict | None = None
    reason: str = ""
    normalisations: list = field(default_factory=list)
    kind: str = "auxiliary"
    vacuity: dict = field(default_factory=dict)
    not_proved: list = field(default_factory=list)
    #: ``{"budget": units, "used": units}``: z3's work budget for the proof and what it used
    rlimit: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "id": self.id,
            "kind": self.kind,
            "statement": self.statement,
            "cites": list(self.cites),
            "not_proved": list(self.not_proved),
            "status": self.status,
            "seconds": round(self.seconds, 4),
            "rlimit": dict(self.rlimit),
            "premises_satisfiable": self.premises_satisfiable,
            "negative_control": dict(self.negative_control),
            "vacuity": dict(self.vacuity),
            "counterexample": self.counterexample,
            "reason": self.reason,
            "normalisations": list(self.normalisations),
        }


# ------------------------------------------------------------- registry

def _suite() -> tuple:
    """``(LEMMAS, EXTRA_LEMMAS)``: the normalisation lemmas, then each lemma set of the
    algorithm registry in its order (:func:`~swarmproof.reference_impl.registry.lemma_sets`)."""
    lemmas = {lem.id: lem for lem in NORMALISATION_LEMMAS}
    extra: dict = {}
    for module in lemma_sets():
        for table, more in ((lemmas, module.LEMMAS), (extra, getattr(module, "EXTRA_LEMMAS", {}))):
            for lid, lem in more.items():
                if lid in lemmas or lid in extra:
                    raise ValueError(f"lemma id={lid!r} of {module.__name__} is already taken")
                table[lid] = lem
    return lemmas, extra


#: The suite, by id (``swarmproof prove`` with no ids runs all of these);
#: :data:`EXTRA_LEMMAS`: run only when named (known-false variants, findings, and true
#: lemmas too hard for z3: the honest timeout).
LEMMAS, EXTRA_LEMMAS = _suite()


def case_families() -> dict:
    """Lemmas stated directly on every small case (``CASE_FAMILIES`` of each lemma set), by id."""
    out: dict = {}
    for module in lemma_sets():
        out.update(getattr(module, "CASE_FAMILIES", {}))
    return out

def lookup(ids: Iterable[str] | None = None) -> list:
    """The lemmas named by ``ids`` (all of :data:`LEMMAS` when None), in order.

    Raises
    ------
    UsageError
        For an unknown id, listing the valid ones.

    Examples
    --------
    >>> [lem.id for lem in lookup(["bounded_range"])]
    ['bounded_range']
    >>> lookup(["lemma7"])
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: lemma='lemma7' is not a known lemma id; fix: use one of: translation_invariance, rotation_invariance, scale_invariance, bounded_range, bounded_range_strict, nclb_link_kept, spanning_tree_kept, relocate_stays_in_range, safe_region_nonempty, intermediate_goal_in_region, wang2020_time_normalisation, wang2020_planner_vertex_one_moment, wang2020_planner_edge_one_moment, wang2020_lemma_iv_a_1, wang2020_theorem_iv_a_2, wang2020_separation_equal_speeds, wang2020_speed_buffer_v_b3_cases, wang2020_separation_speeds, gather_follower_link_kept (run only when named: bounded_range_strict_closed, intermediate_goal_partial_progress, nclb_three_children_direct)
    """
    if ids is None:
        return list(LEMMAS.values())
    out = []
    for i in ids:
        if not isinstance(i, str):          # a lemma an algorithm declares itself (issue 32)
            out.append(_own_lemma(i))
            continue
        lem = LEMMAS.get(i) or EXTRA_LEMMAS.get(i)
        if lem is None:
            raise UsageError(
                f"lemma={i!r} is not a known lemma id{did_you_mean(i, [*LEMMAS, *EXTRA_LEMMAS])}",
                fix="use one of: " + ", ".join(LEMMAS)
                    + " (run only when named: " + ", ".join(EXTRA_LEMMAS) + ")")
        out.append(lem)
    return out


def _own_lemma(entry) -> Lemma:
    """A lemma an algorithm declares as an object: a :class:`~swarmproof.invariants.lemma_api.LemmaSpec`
    (its ``lemma()``) or a :class:`Lemma`."""
    from swarmproof.invariants.lemma_api import LemmaSpec

    if isinstance(entry, LemmaSpec):
        return entry.lemma()
    if isinstance(entry, Lemma):
        return entry
    raise UsageError(f"lemmas entry={entry!r} is neither a lemma id nor a LemmaSpec",
                     fix="declare lemma ids of `swarmproof list lemmas`, or LemmaSpec objects "
                         "(swarmproof.invariants.lemma_api; docs/lemmas.md)")


def _lemma_id(entry) -> str:
    return entry if isinstance(entry, str) else getattr(entry, "id", repr(entry))


def algorithm_lemmas(algorithm: str) -> list:
    """The lemmas an algorithm declares (its class attribute ``lemmas``): what ``swarmproof
    prove --algorithm REF`` proves.  ``algorithm`` is a registry name or ``module:qualname``.
    Each entry is a suite lemma's id or a lemma of the algorithm's own (a ``LemmaSpec``,
    docs/lemmas.md), returned as declared.

    Raises
    ------
    UsageError
        An unknown algorithm; one that declares no lemmas (naming those that do); a declared
        id that is not in the suite.
    """
    from swarmproof.checkers.algorithm_spec import resolve_algorithm

    spec = resolve_algorithm(algorithm)
    ids = list(getattr(spec.factory, "lemmas", None) or ())
    if not ids:
        having = sorted(name for name, declared in lemma_algorithms_by_name().items() if declared)
        raise UsageError(f"algorithm={algorithm!r} declares no lemmas (its class attribute lemmas)",
                         fix=f"name lemma ids instead, or use an algorithm that declares some: {', '.join(having)} "
                             "(`swarmproof list lemmas` names each lemma's algorithms)")
    for i in ids:
        if not isinstance(i, str):
            _own_lemma(i)                   # a LemmaSpec of its own: proved as declared
            continue
        if i not in LEMMAS and i not in EXTRA_LEMMAS:
            raise UsageError(f"algorithm {algorithm!r} declares lemma={i!r}, which is not in the suite"
                             f"{did_you_mean(i, [*LEMMAS, *EXTRA_LEMMAS])}",
                             fix="fix the algorithm's lemmas attribute (ids of `swarmproof list lemmas`)")
    return ids


def lemma_algorithms_by_name() -> dict:
    """``{registry name: [lemma ids it declares]}`` of every registered algorithm."""
    from swarmproof.reference_impl.registry import algorithm_factory, algorithm_names

    return {name: [_lemma_id(e) for e in getattr(algorithm_factory(name), "lemmas", None) or ()]
            for name in algorithm_names()}


def algorithms_of_lemmas() -> dict:
    """``{lemma id: [registry names of the algorithms that declare it]}`` (empty lists for lemmas
    no algorithm declares, e.g. the normalisation lemmas every other one relies on)."""
    out: dict = {i: [] for i in [*LEMMAS, *EXTRA_LEMMAS]}
    for name, ids in lemma_algorithms_by_name().items():
        for i in ids:
            out.setdefault(i, []).append(name)
    return out


# ------------------------------------------------------------- solving

def _configure() -> None:
    """Fix z3's random seeds: the same lemma gives the same answer and model."""
    z3.set_param("smt.random_seed", 0)
    z3.set_param("sat.random_seed", 0)
    z3.set_param("nlsat.seed", 0)


def _solver(timeout_ms: float, params: Sequence = (), ctx: z3.Context | None = None,
            rlimit: int = 0) -> z3.Solver:
    # The solver for the lemma's arithmetic (invariants.lemmas.lemma_solver: nlsat, or the SMT
    # solver on request).  ``rlimit`` (0: none) is z3's resource limit for the next check, counted
    # from the context's count now.  The params come last; prove refuses a lemma whose params set
    # timeout or rlimit (_check_solver_params).
    params = tuple(params)
    s = lemma_solver(ctx, params)
    s.set("timeout", max(1, int(timeout_ms)))
    if rlimit:
        s.set("rlimit", int(rlimit))
    for k, v in params:
        if k != "solver":
            s.set(k, v)
    return s


@dataclass
class Budget:
    """z3's work budget for one proof: ``rlimit`` resource units (deterministic: the same on a
    loaded machine and an idle one, for one z3 version) and an outer wall-clock ``deadline``
    (``time.perf_counter()`` seconds), which only a machine far slower than expected reaches.
    ``used`` counts the units spent so far."""

    rlimit: int
    deadline: float
    used: int = 0

    @classmethod
    def of(cls, rlimit: int | None, timeout_s: float) -> "Budget":
        return cls(int(rlimit or DEFAULT_RLIMIT), time.perf_counter() + timeout_s)

    @property
    def left(self) -> int:
        return self.rlimit - self.used

    def spent_reason(self) -> str:
        return f"z3's budget of rlimit={self.rlimit} was spent"


#: the z3 context of the encoding being solved (Ctrl-C cancels it: :func:`_holding_ctrl_c`)
_CURRENT_CTX: list = [None]


def _cancel_current() -> None:
    ctx = _CURRENT_CTX[0]
    if ctx is not None:
        ctx.interrupt()


def _holding_ctrl_c(fn):
    """Run ``fn`` with Ctrl-C held (:func:`swarmproof.models.interrupt.deferred`): a press cancels
    the z3 check under way and is raised at the next safe point.  z3's Python objects free native
    memory in ``__del__``; a ``KeyboardInterrupt`` landing there is printed as "Exception ignored"
    with a traceback (seen with a fresh context per encoding: many more objects freed)."""
    import functools

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        from swarmproof.models.interrupt import deferred

        with deferred(_cancel_current):
            return fn(*args, **kwargs)
    return wrapper


class _Session:
    """One fresh z3 context for one encoding's solver calls.

    A fresh context makes the answers, the models and the resource counts of a lemma independent
    of what was solved before in the process (in z3's main context, term ids left by earlier
    lemmas changed the models of later ones: ``prove X`` alone and ``prove`` of the whole suite
    gave different negative-control counterexamples)."""

    def __init__(self, budget: Budget, params) -> None:
        self.ctx = z3.Context()
        _CURRENT_CTX[0] = self.ctx
        self.budget = budget
        self.params = tuple(params)
        self.count = 0  # the context's rlimit count after the last check

    def term(self, t):
        return t.translate(self.ctx)

    def check(self, premises: list, negate) -> tuple:
        """One fresh solver: ``premises`` (name, term) tracked by name and optionally
        ``Not(negate)``, with the budget left.

        Returns (z3 result, model or None, reason_unknown); the result is None when the budget
        was already spent (nothing was checked): reason ``"timeout"`` or ``"rlimit"``."""
        from swarmproof.models.interrupt import raise_if_interrupted

        raise_if_interrupted()
        left_ms = (self.budget.deadline - time.perf_counter()) * 1000
        if left_ms <= 0:
            return None, None, "timeout"
        if self.budget.left <= 0:
            return None, None, "rlimit"
        s = _solver(left_ms, self.params, self.ctx, self.budget.left)
        for k, (name, term) in enumerate(premises):
            s.assert_and_track(self.term(term), z3.Bool(f"{k}:{name}", self.ctx))
        if negate is not None:
            s.add(z3.Not(self.term(negate)))
        res = check_interruptibly(s)
        raise_if_interrupted()
        stats = s.statistics()
        if "rlimit count" in stats.keys():
            count = int(stats.get_key_value("rlimit count"))
            self.budget.used += count - self.count
            self.count = count
        if res == z3.sat:
            return res, s.model(), ""
        if res == z3.unknown:
            why = s.reason_unknown()
            if self.budget.left <= 0:
                why = f"{self.budget.spent_reason()} ({why})"
            return res, None, why
        return res, None, ""


def check_interruptibly(solver) -> "z3.CheckSatResult":
    """``solver.check()`` that Ctrl-C stops at once.

    z3 left alone puts its own SIGINT handler in place while it works: it cancels the solver,
    answers ``unknown`` and the suite runs on (the press is lost).  Here z3's handler is off
    (``ctrl_c=False``), the check runs on a helper thread, and the main thread waits for it: a
    Ctrl-C raises ``KeyboardInterrupt`` there at once, interrupts z3 (``Context.interrupt``),
    waits for the solver to return and passes the interrupt on (exit 130,
    swarmproof.models.interrupt).
    """
    import threading

    from swarmproof.models.interrupt import note

    try:
        solver.set("ctrl_c", False)
    except z3.Z3Exception:  # pragma: no cover - a z3 without the parameter
        pass
    if threading.current_thread() is not threading.main_thread():
        return solver.check()          # no Ctrl-C reaches this thread
    out: list = []

    def work() -> None:
        try:
            out.append(solver.check())
        except BaseException as exc:  # noqa: BLE001 - handed to the main thread
            out.append(exc)

    worker = threading.Thread(target=work, name="swarmproof-z3", daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(0.05)
    except KeyboardInterrupt:
        note()
        solver.ctx.interrupt()
        worker.join()
        raise
    if isinstance(out[0], BaseException):
        raise out[0]
    return out[0]


def _number(val) -> float:
    if z3.is_rational_value(val):
        return float(Fraction(val.numerator_as_long(), val.denominator_as_long()))
    if z3.is_algebraic_value(val):
        r = val.approx(20)
        return float(Fraction(r.numerator_as_long(), r.denominator_as_long()))
    if z3.is_int_value(val):
        return float(val.as_long())
    if z3.is_true(val) or z3.is_false(val):     # a Boolean variable (lemma_api.Bool): 1 yes, 0 no
        return float(z3.is_true(val))
    raise TypeError(f"value={val!r} is not a number")  # pragma: no cover


def model_to_numbers(model: z3.ModelRef, variables: Sequence) -> dict:
    """The model's value of each variable as a float (algebraic numbers to 20
    decimals first), keyed by variable name; unconstrained ones are 0.

    Examples
    --------
    >>> x, y = z3.Reals("x y")
    >>> s = z3.Solver(); s.add(x * x == 2, x > 0, y == 1 / 4); _ = s.check()
    >>> model_to_numbers(s.model(), [x, y])
    {'x': 1.4142135623730951, 'y': 0.25}
    """
    return {str(v): _number(model.eval(v, model_completion=True)) for v in variables}


def _cases(enc: Encoding) -> list:
    if not enc.cases:
        return [("", list(enc.premises))]
    return [(name, list(enc.premises) + list(extra)) for name, extra in enc.cases]


def _outcome(status: str, premises_satisfiable, reason: str = "", counterexample=None) -> dict:
    return dict(status=status, premises_satisfiable=premises_satisfiable,
                counterexample=counterexample, reason=reason)


def _not_checked(reason: str) -> str:
    """Why a check did not run: the outer wall-clock cap or the rlimit budget."""
    return "timeout" if reason == "timeout" else "z3's rlimit budget spent"


def _solve_encoding(enc: Encoding, budget: Budget, params) -> dict:
    """Premises satisfiable, then validity, case by case (and part by part), in one fresh z3
    context (:class:`_Session`) on ``budget``.  Returns a dict with ``status``,
    ``premises_satisfiable``, ``counterexample``, ``reason``."""
    session = _Session(budget, params)
    for case, prem in _cases(enc):
        where = f" (case {case})" if case else ""
        r, _, why = session.check(prem, None)
        if r is None:
            return _outcome("inconclusive", None, f"{_not_checked(why)} before checking the premises{where}")
        if r == z3.unsat:
            return _outcome("inconclusive", False,
                            f"premises unsatisfiable{where}: the lemma would hold vacuously")
        if r == z3.unknown:
            return _outcome("inconclusive", None, f"z3 unknown on the premises{where}: {why}")
        for part, concl in (enc.parts or [("", enc.conclusion)]):
            what = f"the conclusion part {part}" if part else "the conclusion"
            r, model, why = session.check(prem, concl)
            if r is None:
                return _outcome("inconclusive", True, f"{_not_checked(why)} before checking {what}{where}")
            if r == z3.sat:
                return _outcome("counterexample", True,
                                f"z3 found premises true and {what} false{where}",
                                model_to_numbers(model, [session.term(v) for v in enc.variables]))
            if r == z3.unknown:
                return _outcome("inconclusive", True,
                                f"z3 unknown on the negated {what[4:]}{where}: {why}")
    return _outcome("proved", True)


@_holding_ctrl_c
def solve(enc: Encoding, params: Sequence = (), *, rlimit: int | None = None,
          timeout_s: float = DEFAULT_TIMEOUT_S) -> dict:
    """Solve one encoding on its own (premises satisfiable, then validity), without the
    negative control and vacuity controls of :func:`prove`: a dict with ``status``,
    ``premises_satisfiable``, ``counterexample``, ``reason``.

    >>> solve(LEMMAS["bounded_range"].build())["status"]
    'proved'
    """
    return _solve_encoding(enc, Budget.of(check_rlimit(rlimit), _check_timeout(timeout_s)), params)


def _without(enc: Encoding, names) -> Encoding:
    """``enc`` with the premises called ``names`` removed (from the common list and every case)."""
    def keep(lst):
        return [(n, t) for n, t in lst if n not in names]

    return Encoding(premises=keep(enc.premises), conclusion=enc.conclusion, variables=enc.variables,
                    cases=[(c, keep(extra)) for c, extra in enc.cases], parts=enc.parts)


def premise_names(enc: Encoding) -> list:
    """Every named premise of ``enc`` (common ones, then each case's), each once, in order."""
    out: list = []
    for name, _ in list(enc.premises) + [p for _, extra in enc.cases for p in extra]:
        if name not in out:
            out.append(name)
    return out


@_holding_ctrl_c
def vacuity_controls(lemma: Lemma, timeout_s: float = DEFAULT_TIMEOUT_S, *,
                     budget: Budget | None = None) -> dict:
    """Drop each premise of ``lemma`` in turn, then all of them, and solve again (issue 19).

    A premise the conclusion needs gives a counterexample when dropped; a lemma whose
    conclusion survives dropping every premise is *tautological* (it says nothing about the
    premises it lists).  ``verdict``: ``"ok"`` (some premise is needed and the lemma is not
    tautological), ``"tautological"``, ``"no_single_premise_needed"`` (every single drop still
    proves: the premises are redundant), ``"identity"`` (no premises at all: a normalisation
    identity, nothing to drop) or ``"inconclusive"`` (a solver timeout or ``unknown`` left it
    open).  ``dropped`` maps each premise to the status with it removed.  The whole check
    shares one :class:`Budget`: ``budget`` (:func:`prove` passes the lemma's), else the lemma's
    rlimit with an outer cap of ``timeout_s`` seconds.

    >>> v = vacuity_controls(LEMMAS["relocate_stays_in_range"])
    >>> v["verdict"], v["dropped"]["on_segment"], v["all_dropped"]
    ('ok', 'counterexample', 'counterexample')
    """
    _configure()
    enc = lemma.build()
    names = premise_names(enc)
    if not names:
        return {"verdict": "identity", "dropped": {}, "all_dropped": None,
                "note": "no premises: an identity, nothing to drop"}
    budget = budget or Budget.of(lemma.rlimit, timeout_s)
    params = tuple(lemma.solver_params)
    dropped = {n: _solve_encoding(_without(enc, {n}), budget, params)["status"] for n in names}
    every = _solve_encoding(_without(enc, set(names)), budget, params)["status"]
    needed = sorted(n for n, st in dropped.items() if st == "counterexample")
    if every == "proved":
        verdict, note = "tautological", "the conclusion holds with every premise dropped"
    elif needed:
        verdict, note = "ok", "needed: " + ", ".join(needed)
        undecided = sorted(n for n, st in dropped.items() if st == "inconclusive")
        if undecided:   # the verdict stands (one needed premise rules out a tautology); say what is open
            note += "; undecided (budget, timeout or z3 unknown): " + ", ".join(undecided)
    elif "inconclusive" in dropped.values() or every == "inconclusive":
        verdict, note = "inconclusive", "a spent budget, a timeout or z3 unknown left a drop undecided"
    else:
        verdict, note = "no_single_premise_needed", "each premise alone can be dropped and the lemma still holds"
    return {"verdict": verdict, "dropped": dropped, "all_dropped": every, "note": note}


@_holding_ctrl_c
def prove(lemma: Lemma, timeout_s: float = DEFAULT_TIMEOUT_S, *, rlimit: int | None = None) -> LemmaResult:
    """Prove one lemma and refute its negative control (module docstring, steps 1-3).

    Parameters
    ----------
    lemma : Lemma
        From :data:`LEMMAS` or :data:`EXTRA_LEMMAS`, or your own.
    timeout_s : float
        Outer wall-clock cap for the whole lemma (default 300 s).  The budget that decides is
        ``rlimit``; the cap is there only for a machine far slower than expected (a cap that
        is reached makes the lemma ``inconclusive``, reason ``timeout``).
    rlimit : int, optional
        z3's work budget for the whole proof: the lemma, its negative control and its vacuity
        controls share it, counted in z3's deterministic resource units, so a loaded machine
        gives the same verdict as an idle one (for one z3 version: the baseline's ``made_by``
        records it).  Default: the lemma's own ``rlimit``, else :data:`DEFAULT_RLIMIT`.
        The result's ``rlimit`` says the budget and what the proof used of it.

    Returns
    -------
    LemmaResult
        ``status`` is ``proved`` only if z3 answered ``unsat`` for the negated
        conclusion, the premises are satisfiable and the control was refuted.

    Raises
    ------
    UsageError
        If ``timeout_s`` is not a positive number or ``rlimit`` not a positive integer.
    """
    timeout_s = _check_timeout(timeout_s)
    rlimit = check_rlimit(lemma.rlimit if rlimit is None else rlimit, f"for lemma {lemma.id!r}")
    _check_solver_params(lemma)
    _configure()
    params = tuple(lemma.solver_params)
    t0 = time.perf_counter()
    budget = Budget.of(rlimit, timeout_s)
    main = _solve_encoding(lemma.build(), budget, params)
    ctrl = _solve_encoding(lemma.control(), budget, params)
    control = {"status": ctrl["status"], "counterexample": ctrl["counterexample"],
               "weakened": lemma.control_note}
    if ctrl["status"] != "counterexample":
        control["reason"] = ctrl["reason"] or "the weakened lemma was proved"
    status, reason = main["status"], main["reason"]
    if status == "proved" and ctrl["status"] != "counterexample":
        status = "inconclusive"
        reason = (f"negative control not refuted ({control['reason']}): "
                  "the encoding may be unable to fail")
    vac = vacuity_controls(lemma, budget=budget) if status == "proved" else {
        "verdict": "not_run", "dropped": {}, "all_dropped": None, "note": f"the lemma is {status}"}
    if status == "proved" and vac["verdict"] not in ("ok", "identity"):
        status = "inconclusive"
        reason = f"vacuity control {vac['verdict']}: {vac['note']}"
    seconds = time.perf_counter() - t0
    return LemmaResult(
        id=lemma.id, statement=lemma.statement, cites=list(lemma.cites), status=status,
        seconds=seconds, premises_satisfiable=main["premises_satisfiable"],
        negative_control=control, counterexample=main["counterexample"], reason=reason,
        normalisations=list(lemma.normalisations), kind=lemma.kind, vacuity=vac,
        not_proved=list(lemma.not_proved), rlimit={"budget": budget.rlimit, "used": budget.used})


def _check_solver_params(lemma: Lemma) -> None:
    """A lemma's ``solver_params`` may tune the solver, not its budget: ``timeout`` would bring the
    wall clock back into the verdict and ``rlimit`` would bypass the recorded budget."""
    for key, value in lemma.solver_params:
        if key in ("timeout", "rlimit"):
            raise UsageError(f"lemma {lemma.id!r} sets solver_params {key}={value!r}",
                             fix="give z3's work budget as Lemma(rlimit=N) (or prove --rlimit N); "
                                 "the wall-clock cap is prove's --timeout")


def _check_timeout(timeout_s) -> float:
    timeout_s = check_positive("timeout", timeout_s, fix="give a timeout in seconds > 0")
    if timeout_s > MAX_TIMEOUT_S:
        raise UsageError(f"timeout={timeout_s!r} seconds is over one day (z3 takes 32-bit milliseconds)",
                         fix=f"give a timeout of at most {MAX_TIMEOUT_S:g} seconds")
    return timeout_s


def check_rlimit(rlimit, where: str = "z3's work budget") -> int | None:
    """``rlimit`` if it is None or an integer in 1..2**32-1 (z3 takes an unsigned 32-bit count),
    else a :class:`UsageError` naming ``where``.

    >>> check_rlimit(5_000_000), check_rlimit(None)
    (5000000, None)
    >>> check_rlimit(0)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: rlimit=0 (z3's work budget) must be an integer from 1 to 4294967295 (z3's resource units); fix: give a positive integer, e.g. 200000000 (the default)
    """
    if rlimit is None:
        return None
    if isinstance(rlimit, bool) or not isinstance(rlimit, (int, np.integer)) or not 1 <= rlimit <= MAX_RLIMIT:
        raise UsageError(f"rlimit={rlimit!r} ({where}) must be an integer from 1 to {MAX_RLIMIT} "
                         "(z3's resource units)", fix=f"give a positive integer, e.g. {DEFAULT_RLIMIT} (the default)")
    return int(rlimit)


def run_suite(ids: Iterable[str] | None = None,
              timeout_s: float = DEFAULT_TIMEOUT_S, *, rlimit: int | None = None,
              progress: Callable[[str], None] | None = None) -> list:
    """Prove the named lemmas (all of :data:`LEMMAS` when ``ids`` is None).

    This is what ``swarmproof prove`` and ``swarmproof verify`` call.

    Raises
    ------
    UsageError
        Unknown lemma id, a non-positive timeout or a bad ``rlimit`` (which, when given,
        replaces every lemma's own budget).

    ``progress``, if given, is called with ``"k/N lemma_id"`` before each lemma (``swarmproof
    prove`` shows it on a terminal).
    """
    _check_timeout(timeout_s)
    check_rlimit(rlimit)
    lemmas = lookup(ids)
    out = []
    for k, lem in enumerate(lemmas, 1):
        if progress is not None:
            progress(f"{k}/{len(lemmas)} {lem.id}")
        out.append(prove(lem, timeout_s, rlimit=rlimit))
    return out


# ------------------------------------- direct confirmation on small trees

@_holding_ctrl_c
def confirm_trees(max_robots: int = 5, timeout_s: float = 60.0, *, symmetry: bool = True,
                  bounded_range: str = "phi_minus_vdt", lemma: str = "spanning_tree_kept",
                  rlimit: int = CASE_RLIMIT) -> dict:
    """Confirm ``spanning_tree_kept`` with z3 directly on every tree shape of
    2..``max_robots`` robots, every root and every subset of moving robots.

    Each case is one whole-tree statement (the lemma set's case family, e.g.
    ``swarmproof.reference_impl.song2016.lemmas.tree_case_encoding``), solved like a
    lemma (premises satisfiable, then validity), its conclusion proved link by link
    with all the tree's premises.

    Parameters
    ----------
    max_robots : int
        Largest tree (at least 2).
    timeout_s : float
        Outer wall-clock cap per case (per class with ``symmetry``); a case that
        reaches it is ``inconclusive``, never counted as confirmed.
    rlimit : int
        z3's work budget per case (per class), in its deterministic resource units: the
        budget that decides (:func:`prove`); a case that spends it is ``inconclusive``.
    symmetry : bool
        Solve one representative per isomorphism class (the family's key, e.g. ``rooted_shape``)
        and give every case of the class its answer; ``False`` solves every case.
    bounded_range : {"phi_minus_vdt", "phi"}
        ``"phi"`` runs the negative control: NCLB with the bounded range of
        radius ``phi``; every case where a moving parent has a moving child
        must then be refuted.
    lemma : str
        The case family (:func:`case_families`); its ``variants`` are the radii.

    Returns
    -------
    dict
        ``counts``: cases by status (``proved``, ``counterexample``,
        ``inconclusive``); ``not_proved``: the cases that were not proved, as
        ``(n, edges, root, moving, status, reason)``; ``cases``: the number of
        cases; ``classes``: the number of z3 problems solved;
        ``class_counts``: those problems by status.  A counterexample would
        contradict the composition argument of docs/proofs.md.

    Raises
    ------
    UsageError
        If ``max_robots`` is not an integer >= 2, ``timeout_s`` is not positive or
        ``bounded_range`` is not one of the two radii.

    Examples
    --------
    >>> out = confirm_trees(2)
    >>> out["counts"], out["cases"], out["classes"]
    ({'proved': 8, 'counterexample': 0, 'inconclusive': 0}, 8, 4)
    >>> confirm_trees(2, bounded_range="phi")["counts"]
    {'proved': 6, 'counterexample': 2, 'inconclusive': 0}
    """
    if isinstance(max_robots, bool) or not isinstance(max_robots, int) or max_robots < 2:
        raise UsageError(f"max_robots={max_robots!r} must be an integer >= 2",
                         fix="give the largest tree size, for example 5")
    timeout_s = _check_timeout(timeout_s)
    rlimit = check_rlimit(rlimit)
    families = case_families()
    if lemma not in families:
        raise UsageError(f"lemma={lemma!r} has no case family", fix=f"use one of {sorted(families)}")
    family = families[lemma]
    if bounded_range not in family.variants:
        raise UsageError(f"bounded_range={bounded_range!r} is not a radius",
                         fix=f"use {family.variants[0]!r} (the lemma) or {family.variants[1]!r} (the negative control)")
    _configure()
    counts = {"proved": 0, "counterexample": 0, "inconclusive": 0}
    class_counts = dict(counts)
    solved: dict = {}
    not_proved = []
    for case in family.cases(max_robots):
        n, tree, root, moving = case
        edges = sorted(tree.edges())
        key = family.key(case) if symmetry else (n, tuple(edges), root, moving)
        if key not in solved:
            r = _solve_encoding(family.encode(case, bounded_range), Budget.of(rlimit, timeout_s),
                                family.solver_params)
            solved[key] = (r["status"], r["reason"])
            class_counts[r["status"]] += 1
        status, reason = solved[key]
        counts[status] += 1
        if status != "proved":
            not_proved.append((n, edges, root, sorted(moving), status, reason))
    return {"counts": counts, "not_proved": not_proved, "cases": sum(counts.values()),
            "classes": len(solved), "class_counts": class_counts}


# ------------------------------------------- the geometry kernel as oracle

def _q(x) -> z3.ArithRef:
    f = Fraction(float(x))
    return z3.RealVal(f.numerator) / f.denominator if f.denominator != 1 else z3.RealVal(f.numerator)


@_holding_ctrl_c
def kernel_oracle_check(kernel, c1, r1, c2, r2, target, *, tol: float = 1e-9,
                        timeout_s: float = 60.0) -> tuple:
    """Check one output of ``nearest_point_in_disc_intersection`` with z3.

    Exact rational arithmetic on the kernel's float inputs and output: the
    output must lie in both closed discs up to ``tol``, and z3 must find no
    point of the intersection nearer ``target`` by more than ``tol``
    (``unsat``).  ``None`` from the kernel must mean no point lies in both
    discs shrunk by ``tol``.

    Returns
    -------
    (status, reason): status ``'confirmed'``, ``'refuted'`` or ``'inconclusive'``.

    Examples
    --------
    >>> from swarmproof.models.geometry import nearest_point_in_disc_intersection as k
    >>> kernel_oracle_check(k, (0, 0), 0.25, (1, 0), 0.75, (0.3, 0.3))[0]
    'confirmed'
    >>> kernel_oracle_check(lambda *a: (0.0, 0.0), (0, 0), 0.25, (1, 0), 0.75, (0.3, 0.3))[0]
    'refuted'
    """
    _configure()
    q = kernel(c1, r1, c2, r2, target)
    x = _pt("x")
    C1, C2, T = (_q(c1[0]), _q(c1[1])), (_q(c2[0]), _q(c2[1])), (_q(target[0]), _q(target[1]))
    R1, R2 = _q(r1), _q(r2)

    def decide(*terms) -> tuple:
        session = _Session(Budget.of(CASE_RLIMIT, timeout_s), ())
        res, model, why = session.check([(f"c{k}", t) for k, t in enumerate(terms)], None)
        if res is None:
            return "inconclusive", _not_checked(why), None
        if res == z3.sat:
            return "sat", "", model_to_numbers(model, [session.term(v) for v in x])
        return ("unsat", "", None) if res == z3.unsat else ("inconclusive", why, None)

    if q is None:
        if min(float(r1), float(r2)) < tol:
            return "inconclusive", "kernel returned None and a radius is below the tolerance"
        res, why, point = decide(dist2(x, C1) <= (R1 - tol) * (R1 - tol), dist2(x, C2) <= (R2 - tol) * (R2 - tol))
        if res == "unsat":
            return "confirmed", "empty intersection confirmed"
        if res == "sat":
            return "refuted", f"kernel returned None but {point} is in both discs"
        return "inconclusive", why
    Q = (_q(q[0]), _q(q[1]))
    for name, C, R in (("first", C1, R1), ("second", C2, R2)):
        if not z3.is_true(z3.simplify(dist2(Q, C) <= (R + tol) * (R + tol))):
            return "refuted", f"output {list(map(float, q))} outside the {name} disc"
    dq = float(np.hypot(float(q[0]) - float(target[0]), float(q[1]) - float(target[1])))
    if dq <= tol:
        return "confirmed", "output is the target"
    res, why, point = decide(dist2(x, C1) <= R1 * R1, dist2(x, C2) <= R2 * R2, dist2(x, T) < _q((dq - tol) ** 2))
    if res == "unsat":
        return "confirmed", "no point of the region nearer the target"
    if res == "sat":
        return "refuted", f"{point} is in the region and nearer the target"
    return "inconclusive", why
