"""A lemma declared once, read two ways: z3 terms for its proof, floats for a run (issue 32).

A :class:`LemmaSpec` holds a lemma's variables (:class:`Real`, :class:`Point`; the yes/no and
whole-number kinds :class:`Bool`, :class:`Int`, :class:`IntPoint`), its named premises and its
conclusion as Python functions of those variables, its citation, kind, gaps and negative
control.  The functions are written with this module's helpers -- the comparisons :func:`Le`
:func:`Lt` :func:`Ge` :func:`Gt` :func:`Eq` :func:`Ne`, the connectives :func:`And` :func:`Or`
:func:`Not` :func:`Implies` :func:`Iff` :func:`Xor` (a :class:`Bool` variable is a formula
itself), :func:`If`, the vector helpers :func:`sub` :func:`add` :func:`scale` :func:`dist2`,
:func:`constant` -- and Python's ``+ - *``, which mean the same on z3 terms and on floats.  From
the one definition:

* :meth:`LemmaSpec.lemma` is the :class:`~swarmproof.invariants.lemmas.Lemma` the prover
  proves (``swarmproof.checkers.proofs``): the functions called on z3 variables;
* :meth:`LemmaSpec.judge` evaluates the same functions on float values (a run's step, a
  counterexample): each premise with the tolerance that makes it *harder* to satisfy, the
  conclusion with the one that makes it *easier*, so float noise can neither fake a premise nor
  hide a failed conclusion ("premises held, conclusion false" is then a real transfer failure);
* :func:`cross_check` draws float values where the premises hold and checks the conclusion in
  floating point: it finds a lemma whose real-number truth does not survive floats.

A yes/no variable is a z3 Boolean in the proof and a truth value in a judgment (judged exactly);
an integer one a z3 integer and a Python ``int``.  With ``sort="real"`` either stays a z3 real
(a :class:`Bool` then means yes iff it equals 1), the form of encodings whose counterexamples
list numbers; :func:`cross_check` still draws 0/1 and whole numbers for them.

Tolerances (``tol``, default :data:`TOL`, in the lemma's normalised units): in a premise,
``Le(a, b)`` is ``a <= b - tol``, ``Lt(a, b)`` is ``a < b - tol``, ``Eq(a, b)`` is ``a == b``
exactly; in the conclusion ``Le(a, b)`` is ``a <= b + tol``, ``Lt(a, b)`` is ``a < b + tol``,
``Eq(a, b)`` is ``|a - b| <= tol``.  :func:`Not` (and the left side of :func:`Implies`) turns the
direction round, so a negated comparison is judged as strictly as a plain one.  z3 reads every
comparison exactly.

Examples
--------
>>> spec = LemmaSpec(
...     id="half_below_one", statement="0 <= x <= 1 implies x / 2 <= 1",
...     variables=(Real("x"),),
...     premises=(("x_in_unit", lambda v: And(Ge(v.x, 0), Le(v.x, 1))),),
...     conclusion=lambda v: Le(v.x * 0.5, 1),
...     cites=("example",), control_note="x up to 4",
...     control_premises=(("x_in_unit", lambda v: And(Ge(v.x, 0), Le(v.x, 4))),))
>>> spec.judge({"x": 0.5})
Judgment(premises={'x_in_unit': True}, conclusion=True, cases={}, parts={}, loose={}, loose_cases={})
>>> spec.judge({"x": 1.0}).premises       # at the boundary: not a premise that held (tolerance)
{'x_in_unit': False}
>>> str(spec.lemma().build().conclusion)
'x*1/2 <= 1'
>>> flag = LemmaSpec(
...     id="flag_means_positive", statement="b iff x > 0 implies: b implies x >= 0",
...     variables=(Bool("b"), Real("x")),
...     premises=(("b_iff_positive", lambda v: Iff(v.b, Gt(v.x, 0))),),
...     conclusion=lambda v: Implies(v.b, Ge(v.x, 0)),
...     cites=("example",), control_note="b means nothing",
...     control_premises=(("x_above_minus_1", lambda v: Ge(v.x, -1)),))
>>> flag.judge({"b": True, "x": 0.5}).premises_hold, flag.judge({"b": 1, "x": -0.5}).premises_hold
(True, False)
>>> str(flag.lemma().build().conclusion)
'Implies(b, x >= 0)'
"""

from __future__ import annotations

import contextvars
import dataclasses
import math
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Callable

import numpy as np
import z3

from swarmproof.invariants.lemmas import Encoding, Lemma, add, dist2, lemma_solver, scale, sub

__all__ = ["TOL", "Real", "Point", "Bool", "Int", "IntPoint", "LemmaSpec", "Judgment", "Le", "Lt", "Ge", "Gt", "Eq",
           "Ne", "And", "Or", "Not", "Implies", "Iff", "Xor", "If", "sub", "add", "scale", "dist2", "constant",
           "cross_check"]

#: The default tolerance of a float judgment, in the lemma's normalised units (``phi = 1``): the
#: engine's monitors compare positions with ``1e-9 * phi`` (swarmproof.invariants.premises).
TOL = 1e-9

# ------------------------------------------------------------------ the two readings

#: True while a spec's functions are called on z3 variables (LemmaSpec.lemma's build)
_Z3 = contextvars.ContextVar("swarmproof_lemma_z3", default=False)


class _Formula:
    """A float formula of this module, judged later.  Python's ``and``/``or``/``not`` and
    ``x if c else y`` would read it as a plain truth value (always true) and judge it wrongly,
    so using it as one is an error."""

    def __bool__(self) -> bool:
        raise TypeError("a lemma formula has no plain truth value: combine formulas with And, Or, Not, "
                        "Implies and If of swarmproof.invariants.lemma_api, not Python's and/or/not/if")


@dataclass(frozen=True)
class _Cmp(_Formula):
    """A comparison of two floats, judged later with the direction of its place (premise or
    conclusion, turned round under a negation)."""

    op: str
    a: float
    b: float


@dataclass(frozen=True)
class _Op(_Formula):
    op: str        # "and" | "or" | "not"
    args: tuple


def _is_z3(*xs) -> bool:
    return _Z3.get() or any(isinstance(x, z3.ExprRef) for x in xs)


def _cmp(op: str, a, b):
    if _is_z3(a, b):
        return {"le": lambda: a <= b, "lt": lambda: a < b, "ge": lambda: a >= b, "gt": lambda: a > b,
                "eq": lambda: a == b}[op]()
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):   # a batch of instances (one per entry)
        return _Cmp(op, np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    return _Cmp(op, float(a), float(b))


def Le(a, b):
    """``a <= b``."""
    return _cmp("le", a, b)


def Lt(a, b):
    """``a < b``."""
    return _cmp("lt", a, b)


def Ge(a, b):
    """``a >= b``."""
    return _cmp("ge", a, b)


def Gt(a, b):
    """``a > b``."""
    return _cmp("gt", a, b)


def Eq(a, b):
    """``a == b``."""
    return _cmp("eq", a, b)


def And(*args):
    """Every argument holds (z3.And on z3 terms)."""
    if _is_z3(*args):
        return z3.And(*[_as_z3(x) for x in args])
    return _Op("and", args)


def Or(*args):
    """Some argument holds (z3.Or on z3 terms)."""
    if _is_z3(*args):
        return z3.Or(*[_as_z3(x) for x in args])
    return _Op("or", args)


def Not(a):
    """``a`` does not hold; in a float judgment its comparisons change direction."""
    if _is_z3(a):
        return z3.Not(_as_z3(a))
    return _Op("not", (a,))


def Implies(a, b):
    """``Or(Not(a), b)`` (``z3.Implies`` on z3 terms)."""
    if _is_z3(a, b):
        return z3.Implies(_as_z3(a), _as_z3(b))
    return Or(Not(a), b)


def If(cond, a, b):
    """``a`` where ``cond`` holds, else ``b`` (``z3.If`` on z3 terms).  In floats ``cond`` is
    judged exactly, without a tolerance: a choice between two values has no harder or easier
    side."""
    if _is_z3(cond, a, b):
        return z3.If(_as_z3(cond), a, b)
    t = _truth(cond, True, 0.0)
    if isinstance(t, np.ndarray):
        return np.where(t, a, b)
    return a if t else b


def constant(x, like):
    """The number ``x`` as the kind of ``like``: ``z3.RealVal(x)`` when ``like`` is a z3 term, else
    a float.  Only needed to keep a term exactly as a hand-written encoding built it (z3 orients
    ``term <= RealVal(1)`` as ``1 >= term``, which can change its search, not its answer).  A
    truth value ``True``/``False`` is ``z3.BoolVal(x)``, else a formula with that truth."""
    if isinstance(x, bool):
        return z3.BoolVal(x) if _is_z3(like) else _Truth(x)
    return z3.RealVal(x) if _is_z3(like) else float(x)


def _as_z3(x):
    if isinstance(x, bool):
        return z3.BoolVal(x)
    return x


def _truth(x, strict: bool, tol: float) -> bool:
    """A float formula's truth: ``strict`` (a premise: harder to satisfy) or lenient."""
    if isinstance(x, _Cmp):
        t = -tol if strict else tol
        a, b = x.a, x.b
        if x.op == "le":
            return a <= b + t
        if x.op == "lt":
            return a < b + t
        if x.op == "ge":
            return a >= b - t
        if x.op == "gt":
            return a > b - t
        return a == b if strict else abs(a - b) <= tol
    if isinstance(x, _Op):
        if x.op == "not":
            inner = _truth(x.args[0], not strict, tol)
            return ~inner if isinstance(inner, np.ndarray) else not inner
        vals = [_truth(a, strict, tol) for a in x.args]
        if any(isinstance(t, np.ndarray) for t in vals):     # a batch: element by element
            out = vals[0]
            for t in vals[1:]:
                out = (out & t) if x.op == "and" else (out | t)
            return out
        return all(vals) if x.op == "and" else any(vals)
    if isinstance(x, _Truth):   # a Bool variable's float value, or a constant (section "Booleans and integers")
        return x.value
    raise TypeError(f"formula={x!r} is not a comparison of this module (Le, Lt, Ge, Gt, Eq) or a "
                    "connective of them (And, Or, Not, Implies): a Python comparison such as x <= 1 "
                    "is judged without the tolerances; write it Le(x, 1)")


def _number(x):
    """A variable's float value, or a float array for a batch of instances (a runtime monitor
    judges every instance of a step at once: the formulas work element by element)."""
    return np.asarray(x, dtype=float) if isinstance(x, np.ndarray) else float(x)


# ------------------------------------------------------------------ declarations

@dataclass(frozen=True)
class Real:
    """A real variable.  ``lo``/``hi``: where :func:`cross_check` draws it (the premises, not
    this range, state every constraint)."""

    name: str
    lo: float = -2.0
    hi: float = 2.0

    def names(self) -> list:
        return [self.name]

    def z3(self):
        return z3.Real(self.name)

    def value(self, values: dict):
        return _number(values[self.name])


@dataclass(frozen=True)
class Point:
    """A point variable ``(name_x, name_y)``, each coordinate drawn in ``[lo, hi]``."""

    name: str
    lo: float = -2.0
    hi: float = 2.0

    def names(self) -> list:
        return [f"{self.name}_x", f"{self.name}_y"]

    def z3(self):
        return (z3.Real(f"{self.name}_x"), z3.Real(f"{self.name}_y"))

    def value(self, values: dict):
        return (_number(values[f"{self.name}_x"]), _number(values[f"{self.name}_y"]))


@dataclass(frozen=True)
class Judgment:
    """A float judgment of one instance: each premise's truth (strict) and the conclusion's
    (lenient).  A lemma with cases also has each case's extra premises (``cases``: case name ->
    {premise: truth}); its premises hold when the common ones do and every extra premise of
    some case does.  A lemma with parts has each conjunct's truth (``parts``); the conclusion is
    their conjunction."""

    premises: dict
    conclusion: bool
    cases: dict = field(default_factory=dict)
    parts: dict = field(default_factory=dict)
    #: each premise's truth judged *leniently* (the tolerance that makes it easier to satisfy), and
    #: each case's: a premise false even so failed beyond float noise (a monitor reports it); one
    #: true leniently and false strictly sits at its boundary (a monitor neither reports it nor
    #: judges the conclusion there).  Empty when not asked for (:meth:`LemmaSpec.judge` ``loose``).
    loose: dict = field(default_factory=dict)
    loose_cases: dict = field(default_factory=dict)

    @property
    def premises_hold(self) -> bool:
        if not all(self.premises.values()):
            return False
        return not self.cases or any(all(c.values()) for c in self.cases.values())

    @property
    def failed(self) -> tuple:
        """The premises that failed even judged leniently (a real failure, not float noise): the
        common ones by name; for a lemma with cases, when no case holds leniently, ``"case:NAME"``
        for every case (then :attr:`failed_in_cases` names each case's failed premises).  Empty
        when :attr:`loose` was not computed."""
        bad = tuple(n for n, ok in self.loose.items() if not ok)
        if bad or not self.loose_cases:
            return bad
        if any(all(c.values()) for c in self.loose_cases.values()):
            return ()
        return tuple(f"case:{name}" for name in self.loose_cases)

    @property
    def failed_in_cases(self) -> dict:
        """``{case: (premise, ...)}``: each case's premises that failed leniently."""
        return {case: tuple(n for n, ok in c.items() if not ok) for case, c in self.loose_cases.items()}

    @property
    def case(self) -> str | None:
        """The first case whose extra premises hold (None: no case, or the lemma has none)."""
        return next((name for name, c in self.cases.items() if all(c.values())), None)

    @property
    def transfer_failure(self) -> bool:
        """Premises held and the conclusion did not: the proof does not carry over."""
        return self.premises_hold and not self.conclusion


@dataclass(frozen=True)
class LemmaSpec:
    """A lemma declared once (module docstring).  ``premises`` and ``control_premises`` are
    ``(name, function)`` pairs; each function takes the variables as attributes of one argument
    (``v.s``, ``v.p_i_0``) and returns a formula of this module's helpers.

    ``cases`` (optional) splits the lemma into cases, ``(case name, ((premise name, function),
    ...))``: the lemma holds iff it holds in every case (the common premises plus the case's),
    as the prover proves it (:class:`~swarmproof.invariants.lemmas.Encoding`).  ``parts``
    (optional) names the conjuncts of the conclusion, ``(part name, function)``, each proved on
    its own; the conclusion is then their conjunction (give ``conclusion=None``).
    ``control_cases`` are the negative control's cases (default: the lemma's);
    ``control_conclusion`` / ``control_parts`` its conclusion (default: the lemma's), for a
    control that changes a definition the conclusion reads, not a premise."""

    id: str
    statement: str
    variables: tuple
    premises: tuple
    conclusion: Callable | None
    cites: tuple
    control_note: str
    #: the negative control's premises (the lemma's, one weakened); the conclusion is the lemma's
    control_premises: tuple = ()
    normalisations: tuple = ()
    kind: str = "auxiliary"
    not_proved: tuple = ()
    solver_params: tuple = ()
    rlimit: int | None = None
    tol: float = TOL
    extra: dict = field(default_factory=dict)
    cases: tuple = ()
    parts: tuple = ()
    control_cases: tuple | None = None
    #: the negative control's conclusion or parts, for a control that weakens a definition the
    #: conclusion reads (a decision rule) rather than a premise; None: the lemma's
    control_conclusion: Callable | None = None
    control_parts: tuple | None = None
    #: the negative control is this other lemma's (a finding or a hard lemma whose natural control
    #: is a proved lemma's weakened form, in that lemma's variables)
    control_of: "LemmaSpec | None" = None

    def __post_init__(self) -> None:
        from swarmproof.models.errors import UsageError

        if (self.conclusion is None) == (not self.parts):
            raise UsageError(f"lemma {self.id!r}: give either a conclusion or parts (its named conjuncts)",
                             fix="conclusion=lambda v: ..., or parts=((\"name\", lambda v: ...), ...) and "
                                 "conclusion=None")
        for case in tuple(self.cases) + tuple(self.control_cases or ()):
            if not (isinstance(case, tuple) and len(case) == 2 and isinstance(case[0], str)):
                raise UsageError(f"lemma {self.id!r}: cases entry={case!r} is not (name, premises)",
                                 fix="write each case as (\"name\", ((\"premise\", lambda v: ...), ...))")
        if (not self.control_premises and self.control_conclusion is None and self.control_parts is None
                and self.control_of is None):
            raise UsageError(f"lemma {self.id!r} declares no control_premises (its negative control)",
                             fix="give control_premises: the premises with one weakened, which z3 must "
                                 "refute with a counterexample (docs/proofs.md)")
        groups = [("premises", self.premises), ("control_premises", self.control_premises),
                  ("parts", self.parts), ("control_parts", self.control_parts or ())]
        groups += [(f"cases[{name}]", prem) for name, prem in tuple(self.cases) + tuple(self.control_cases or ())]
        for label, pairs in groups:
            for pair in pairs:
                if not (isinstance(pair, tuple) and len(pair) == 2 and isinstance(pair[0], str)
                        and callable(pair[1])):
                    raise UsageError(f"lemma {self.id!r}: {label} entry={pair!r} is not (name, function)",
                                     fix="write each premise as (\"name\", lambda v: Le(...))")
        self._dry_run()

    def _dry_run(self) -> None:
        """Call every function of the definition once on float values (each variable in the middle
        of its range): a Python comparison or ``and``/``or``/``not``, a misspelt variable or a
        value of the wrong kind is then a usage error naming the lemma and the function, at
        definition, rather than a crash in a run (z3 accepts Python's ``<=``: only the float
        reading would meet it)."""
        from swarmproof.models.errors import UsageError

        values = {}
        for var in self.variables:
            lo, hi = getattr(var, "lo", 0), getattr(var, "hi", 0)
            mid = lo if isinstance(lo, int) and not isinstance(lo, bool) and isinstance(var, (Int, IntPoint)) \
                else (lo + hi) / 2
            for n in var.names():
                values[n] = 1 if isinstance(var, Bool) else mid
        v = self._namespace(lambda var: var.value(values))
        groups = [("premise", self.premises), ("control premise", self.control_premises), ("part", self.parts),
                  ("control part", self.control_parts or ())]
        groups += [(f"case {case!r} premise", extra) for case, extra in tuple(self.cases) + tuple(self.control_cases or ())]
        groups += [("conclusion", (("conclusion", self.conclusion),) if self.conclusion is not None else ()),
                   ("control conclusion", (("control_conclusion", self.control_conclusion),)
                    if self.control_conclusion is not None else ())]
        for label, pairs in groups:
            for name, fn in pairs:
                try:
                    _truth(fn(v), True, 0.0)
                except (TypeError, AttributeError, NameError, KeyError) as exc:
                    raise UsageError(f"lemma {self.id!r}: {label} {name!r} cannot be evaluated on floats: "
                                     f"{type(exc).__name__}: {exc}",
                                     fix="write comparisons with Le/Lt/Ge/Gt/Eq, connectives with And/Or/Not/"
                                         "Implies/If of swarmproof.invariants.lemma_api, and read only the "
                                         f"declared variables ({', '.join(var.name for var in self.variables)})") \
                        from None
                except Exception:  # noqa: BLE001 - e.g. a division by zero at the middle values: not a misuse
                    pass

    def _namespace(self, make) -> SimpleNamespace:
        return SimpleNamespace(**{var.name: make(var) for var in self.variables})

    def _encoding(self, premises, cases) -> Encoding:
        token = _Z3.set(True)
        try:
            v = self._namespace(lambda var: var.z3())
            prem = [(name, _as_z3(fn(v))) for name, fn in premises]
            case_terms = [(case, [(name, _as_z3(fn(v))) for name, fn in extra]) for case, extra in cases]
            parts = [(name, _as_z3(fn(v))) for name, fn in self.parts]
            concl = z3.And([t for _, t in parts]) if parts else _as_z3(self.conclusion(v))
        finally:
            _Z3.reset(token)
        flat = [t for var in self.variables for t in _z3_variables(var)]
        return Encoding(premises=prem, conclusion=concl, variables=flat, cases=case_terms, parts=parts)

    def build(self) -> Encoding:
        """The z3 encoding of the lemma."""
        return self._encoding(self.premises, self.cases)

    def control(self) -> Encoding:
        """The z3 encoding of the negative control."""
        if self.control_of is not None:
            return self.control_of.control()
        spec = self if self.control_parts is None and self.control_conclusion is None else \
            dataclasses.replace(self, parts=self.control_parts or (), conclusion=self.control_conclusion)
        return spec._encoding(self.control_premises,
                              self.cases if self.control_cases is None else self.control_cases)

    def lemma(self) -> Lemma:
        """The :class:`~swarmproof.invariants.lemmas.Lemma` the prover proves."""
        return Lemma(id=self.id, statement=self.statement, cites=tuple(self.cites),
                     normalisations=tuple(self.normalisations), build=self.build, control=self.control,
                     control_note=self.control_note, solver_params=tuple(self.solver_params), kind=self.kind,
                     not_proved=tuple(self.not_proved), rlimit=self.rlimit)

    def names(self) -> list:
        """Every float value a judgment needs, in the order a counterexample lists them."""
        return [n for var in self.variables for n in var.names()]

    def judge(self, values: dict, *, tol: float | None = None, outcome: dict | None = None,
              loose: bool = False, only: tuple | None = None, premise_tol: float | None = None) -> Judgment:
        """The premises (strict) and the conclusion (lenient) on float ``values`` keyed by
        :meth:`names` (a z3 counterexample's dict fits).

        ``outcome`` (optional): values that replace some of ``values`` for the conclusion only
        (a runtime binding that reads what followed apart from what the premises read).
        ``loose``: also judge each premise leniently (:attr:`Judgment.loose`).  ``only``: judge
        just these premises (by name) and not the conclusion (``conclusion`` is then True); the
        values need only the variables they read.  ``premise_tol``: the tolerance against the
        premises (default ``tol``; a runtime monitor judges them exactly, 0: docs/decisions.md)."""
        tol = self.tol if tol is None else tol
        ptol = tol if premise_tol is None else premise_tol
        if only is not None:
            known = {name for name, _ in self.premises} | {n for _, extra in self.cases for n, _ in extra}
            unknown = [n for n in only if n not in known]
            if unknown:
                raise KeyError(f"lemma {self.id!r} has no premise {unknown}; its premises: {sorted(known)}")
            v = _Partial(self.id, {var.name: var.value(values) for var in self.variables
                                   if all(n in values for n in var.names())})
            pairs = [(n, fn) for n, fn in self.premises if n in only]
            pairs += [(n, fn) for _, extra in self.cases for n, fn in extra if n in only]
            prem = {n: _truth(fn(v), True, ptol) for n, fn in pairs}
            lo = {n: _truth(fn(v), False, tol) for n, fn in pairs} if loose else {}
            return Judgment(prem, True, loose=lo)
        missing = [n for n in self.names() if n not in values]
        if missing:
            raise KeyError(f"lemma {self.id!r} needs values for {missing}")
        v = self._namespace(lambda var: var.value(values))
        prem = {name: _truth(fn(v), True, ptol) for name, fn in self.premises}
        cases = {case: {name: _truth(fn(v), True, ptol) for name, fn in extra} for case, extra in self.cases}
        lo, lo_cases = {}, {}
        if loose:
            lo = {name: _truth(fn(v), False, tol) for name, fn in self.premises}
            lo_cases = {case: {name: _truth(fn(v), False, tol) for name, fn in extra}
                        for case, extra in self.cases}
        if outcome:
            w = self._namespace(lambda var: var.value({**values, **outcome}))
        else:
            w = v
        if self.parts:
            parts = {name: _truth(fn(w), False, tol) for name, fn in self.parts}
            return Judgment(prem, all(parts.values()), cases, parts, lo, lo_cases)
        return Judgment(prem, _truth(self.conclusion(w), False, tol), cases, loose=lo, loose_cases=lo_cases)


class _Partial(SimpleNamespace):
    """The variables a partial judgment (``judge(only=...)``) was given; reading another is an
    error that names it."""

    def __init__(self, lemma_id: str, values: dict) -> None:
        super().__init__(**values)
        object.__setattr__(self, "_lemma_id", lemma_id)

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        raise KeyError(f"lemma {self._lemma_id!r}: the premises judged read variable={name!r}, "
                       "which the values do not give")


# ------------------------------------------------------------------ the concrete cross-check

def cross_check(spec: LemmaSpec, *, examples: int = 200, seed: int = 0) -> dict:
    """Draw float values where ``spec``'s premises hold and check its conclusion in floating
    point, with ``spec.tol`` (the tolerances of :meth:`LemmaSpec.judge`).

    Values come from Hypothesis (``examples`` draws from each variable's ``lo..hi``, seeded with
    ``seed``, shrunk to a small failure) and from z3 models of the premises (exact values
    rounded to floats; found even where the premises hold on a thin set that random draws miss).
    Returns ``{"status", "instances", "counterexample", "message"}``: ``"violated"`` with the
    float values where the premises held and the conclusion failed, ``"held"`` when some
    instances had the premises hold and none failed, ``"inconclusive"`` when no instance had
    them hold (vacuous: nothing was checked).  Exploration, not a proof."""
    from hypothesis import HealthCheck, Phase, given, seed as hseed, settings
    from hypothesis import strategies as st

    held = 0
    for values in _z3_models(spec):
        j = spec.judge(values)
        if j.premises_hold:
            held += 1
            if not j.conclusion:
                return _found(spec, values, held)
    draws = st.fixed_dictionaries({n: draw for var in spec.variables for n, draw in _draws(var, st)})
    counted = {"held": 0, "last": None}

    @hseed(seed)
    @settings(max_examples=examples, database=None, deadline=None, print_blob=False, report_multiple_bugs=False,
              suppress_health_check=list(HealthCheck), phases=[Phase.generate, Phase.shrink])
    @given(draws)
    def probe(values) -> None:
        j = spec.judge(values)
        counted["held"] += j.premises_hold
        if j.transfer_failure:
            counted["last"] = values   # Hypothesis runs the shrunk failure last
            raise _Failed

    from swarmproof.models.hypothesis_seed import without_local_constants

    try:
        with without_local_constants():      # the same draws whatever ran before in the process
            probe()
        found = None
    except _Failed:
        found = counted["last"]
    held += counted["held"]
    if found is not None:
        return _found(spec, found, held)
    if not held:
        return {"status": "inconclusive", "instances": 0, "counterexample": None,
                "message": f"no drawn instance of {spec.id} had its premises hold: nothing was checked"}
    return {"status": "held", "instances": held, "counterexample": None,
            "message": f"the conclusion held in floating point on {held} instances where the premises held"}


class _Failed(Exception):
    """A drawn instance where the premises held and the conclusion did not."""


def _found(spec: LemmaSpec, values: dict, held: int) -> dict:
    vals = {n: float(values[n]) for n in spec.names()}
    return {"status": "violated", "instances": held, "counterexample": vals,
            "message": f"premises of {spec.id} held in floating point and the conclusion did not "
                       f"(tolerance {spec.tol:g}): the lemma's real-number truth does not survive floats"}


#: z3's work budget for one case's models in :func:`cross_check` (resource units, deterministic):
#: about a second of work on this project's machine; a case whose models cost more yields fewer.
MODEL_RLIMIT = 5_000_000


def _z3_models(spec: LemmaSpec, count: int = 8) -> list:
    """Up to ``count`` z3 models of the premises (each excluded from the next), as floats; for a
    lemma with cases, up to ``count`` for each case.

    Each case is solved in a fresh z3 context (the models then do not depend on what the process
    solved before, as in ``swarmproof.checkers.proofs``), with the nonlinear procedure the prover
    uses (nlsat; the SMT solver for a lemma whose ``solver_params`` ask for it) and one work budget
    of :data:`MODEL_RLIMIT` for all its models: deterministic, and bounded on any machine."""
    enc = spec.build()
    out = []
    for _, extra in (enc.cases or [("", [])]):
        ctx = z3.Context()
        s = lemma_solver(ctx, spec.solver_params)
        s.set("rlimit", MODEL_RLIMIT)          # a fresh context counts from 0: the budget for them all
        for _, term in list(enc.premises) + list(extra):
            s.add(term.translate(ctx))
        variables = [var.translate(ctx) for var in enc.variables]
        for _ in range(count):
            if s.check() != z3.sat:
                break                           # unsat, or unknown once the budget is spent
            m = s.model()
            vals = {str(var): _float(m.eval(var, model_completion=True)) for var in variables}
            out.append(vals)
            s.add(z3.Or([var != m.eval(var, model_completion=True) for var in variables]))
    return out


def _float(val) -> float:
    if z3.is_rational_value(val):
        return val.numerator_as_long() / val.denominator_as_long()
    if z3.is_algebraic_value(val):
        r = val.approx(20)
        return r.numerator_as_long() / r.denominator_as_long()
    if z3.is_int_value(val):
        return float(val.as_long())
    if z3.is_true(val) or z3.is_false(val):
        return float(z3.is_true(val))
    return math.nan  # pragma: no cover


# ------------------------------------------------------------------ Booleans and integers

# Yes/no choices, whole numbers (grid directions, waypoint offsets) and the connectives on them,
# for lemmas with Boolean structure such as a planner's decision rule (issue 32).  A Bool variable
# is a formula itself: ``And(v.ready, Not(v.blocked))``.  In floats its value is a _Truth (a Python
# bool wrapped as a formula, judged exactly: no tolerance), not a plain bool: a plain bool is what
# Python's own ``x <= 1`` gives, which a judgment refuses (it would skip the tolerances).

@dataclass(frozen=True)
class _Truth(_Formula):
    """A fixed truth value in a float judgment: a Bool variable's value, or ``constant(True or
    False, like)``."""

    value: bool

@dataclass(frozen=True)
class Bool:
    """A yes/no variable, usable directly as a formula: ``z3.Bool(name)``; in floats a Python
    ``bool`` (given as ``True``/``False`` or 1/0; read as a formula of that truth);
    :func:`cross_check` draws it with Hypothesis ``booleans()``.

    ``sort="real"``: a real variable that means *yes* iff it equals 1 (the formula
    ``z3.Real(name) == 1``), for an encoding whose counterexamples must list numbers only (a
    counterexample gives it as 1 or 0, and the judgment reads a value as yes iff it is 1)."""

    name: str
    sort: str = "bool"

    def names(self) -> list:
        return [self.name]

    def z3(self):
        return z3.Real(self.name) == 1 if self.sort == "real" else z3.Bool(self.name)

    def z3_variables(self) -> list:
        return [z3.Real(self.name) if self.sort == "real" else z3.Bool(self.name)]

    def value(self, values: dict):
        x = values[self.name]
        if isinstance(x, np.ndarray):                    # a batch of instances: yes where 1
            return _Truth(np.asarray(x, dtype=float) == 1)
        return _Truth(float(x) == 1)

    def draws(self, st) -> list:
        if self.sort == "real":
            return [(self.name, st.sampled_from((0.0, 1.0)))]
        return [(self.name, st.booleans())]


@dataclass(frozen=True)
class Int:
    """An integer variable: ``z3.Int(name)``; in floats a Python ``int``; :func:`cross_check`
    draws it with Hypothesis ``integers(lo, hi)`` (the premises, not this range, state every
    constraint).

    ``sort="real"``: a real variable (``z3.Real(name)``) whose premises pick whole values (a grid
    direction, a waypoint offset): z3 reads it as any real, as the encoding states it, and the
    cross-check draws whole numbers, where the premises can hold, as floats."""

    name: str
    lo: int = -2
    hi: int = 2
    sort: str = "int"

    def names(self) -> list:
        return [self.name]

    def z3(self):
        return z3.Real(self.name) if self.sort == "real" else z3.Int(self.name)

    def z3_variables(self) -> list:
        return [self.z3()]

    def value(self, values: dict):
        x = values[self.name]
        if isinstance(x, np.ndarray):                    # a batch of instances (one per entry)
            return np.asarray(x, dtype=float) if self.sort == "real" else np.asarray(x, dtype=np.int64)
        return float(x) if self.sort == "real" else int(x)

    def draws(self, st) -> list:
        ints = st.integers(min_value=self.lo, max_value=self.hi)
        return [(self.name, ints.map(float) if self.sort == "real" else ints)]


@dataclass(frozen=True)
class IntPoint:
    """A point ``(name_x, name_y)`` of two :class:`Int` coordinates (a grid waypoint, a unit
    move), each drawn in ``lo..hi``; ``sort`` as :class:`Int`'s."""

    name: str
    lo: int = -2
    hi: int = 2
    sort: str = "int"

    def _coords(self) -> tuple:
        return tuple(Int(f"{self.name}_{c}", self.lo, self.hi, self.sort) for c in "xy")

    def names(self) -> list:
        return [f"{self.name}_x", f"{self.name}_y"]

    def z3(self):
        return tuple(c.z3() for c in self._coords())

    def z3_variables(self) -> list:
        return list(self.z3())

    def value(self, values: dict):
        return tuple(c.value(values) for c in self._coords())

    def draws(self, st) -> list:
        return [d for c in self._coords() for d in c.draws(st)]


def _z3_variables(var) -> list:
    """The z3 variables of one declared variable, in the order a counterexample lists them."""
    if hasattr(var, "z3_variables"):
        return var.z3_variables()
    return list(var.z3()) if isinstance(var, Point) else [var.z3()]


def _draws(var, st) -> list:
    """``(name, Hypothesis strategy)`` for each value of one declared variable (cross_check)."""
    if hasattr(var, "draws"):
        return var.draws(st)
    return [(n, st.floats(min_value=var.lo, max_value=var.hi, allow_nan=False)) for n in var.names()]


def _is_formula(x) -> bool:
    return isinstance(x, _Formula)


def Iff(a, b):
    """``a`` holds iff ``b`` does: the equality of two Booleans (``a == b`` on z3 terms)."""
    if _is_z3(a, b):
        return _as_z3(a) == _as_z3(b)
    return Or(And(a, b), And(Not(a), Not(b)))


def Xor(a, b):
    """Exactly one of ``a`` and ``b`` holds (``z3.Xor`` on z3 terms)."""
    if _is_z3(a, b):
        return z3.Xor(_as_z3(a), _as_z3(b))
    return Or(And(a, Not(b)), And(Not(a), b))


def Ne(a, b):
    """``a != b`` (z3's ``distinct`` on z3 terms; ``Not(Eq(a, b))`` in floats, or ``Not(Iff(a,
    b))`` for Booleans)."""
    if _is_z3(a, b):
        return a != b
    return Not(Iff(a, b)) if _is_formula(a) or _is_formula(b) else Not(Eq(a, b))
