"""Three-valued verdicts, never two (DESIGN.md section 1, "Verdicts").

* ``PROVED`` — a proof (z3 ``unsat`` of the negation, with satisfiable premises);
* ``HELD`` — a check held over everything it examined (a decision procedure
  that examined everything, or exploration that examined *some* things:
  exploration never says proved);
* ``VIOLATED`` — a counterexample exists and is attached;
* ``INCONCLUSIVE`` — timeout, z3 ``unknown``, budget spent, vacuous premises.
  Never a pass.

Exit codes of the command line (DESIGN.md section 2) derive from verdicts:
0 all hold, 1 something violated, 3 inconclusive (2 is for usage errors).

Examples
--------
>>> Verdict.combine([Verdict.PROVED, Verdict.HELD])
<Verdict.HELD: 'held'>
>>> Verdict.combine([Verdict.HELD, Verdict.INCONCLUSIVE]).exit_code
3
>>> Verdict.combine([Verdict.INCONCLUSIVE, Verdict.VIOLATED]).exit_code
1
>>> Verdict.combine([]).exit_code
3
"""

from __future__ import annotations

import enum
from typing import Iterable

__all__ = ["Verdict", "NOT_APPLICABLE", "NotApplicable", "ThreeValued", "STATUSES", "EXIT_OK", "EXIT_VIOLATED", "EXIT_USAGE", "EXIT_INCONCLUSIVE", "EXIT_INTERNAL"]

EXIT_OK = 0
EXIT_VIOLATED = 1
EXIT_USAGE = 2
EXIT_INCONCLUSIVE = 3
#: swarmproof's own bug (never a finding): one line on stderr, the traceback in a file.
EXIT_INTERNAL = 4


class Verdict(str, enum.Enum):
    PROVED = "proved"
    HELD = "held"
    VIOLATED = "violated"
    INCONCLUSIVE = "inconclusive"

    @property
    def passed(self) -> bool:
        """True only for PROVED and HELD."""
        return self in (Verdict.PROVED, Verdict.HELD)

    @property
    def exit_code(self) -> int:
        if self.passed:
            return EXIT_OK
        return EXIT_VIOLATED if self is Verdict.VIOLATED else EXIT_INCONCLUSIVE

    @staticmethod
    def combine(verdicts: Iterable["Verdict"]) -> "Verdict":
        """Worst of several: violated > inconclusive > held > proved.

        An empty collection is INCONCLUSIVE (nothing was checked); :data:`NOT_APPLICABLE`
        is no verdict and is left out (only not-applicable ones: nothing was checked).

        >>> Verdict.combine([NOT_APPLICABLE, Verdict.HELD]), Verdict.combine([NOT_APPLICABLE])
        (<Verdict.HELD: 'held'>, <Verdict.INCONCLUSIVE: 'inconclusive'>)
        """
        vs = [v for v in verdicts if v is not NOT_APPLICABLE]
        if not vs:
            return Verdict.INCONCLUSIVE
        if Verdict.VIOLATED in vs:
            return Verdict.VIOLATED
        if Verdict.INCONCLUSIVE in vs:
            return Verdict.INCONCLUSIVE
        if Verdict.HELD in vs:
            return Verdict.HELD
        return Verdict.PROVED

    def __str__(self) -> str:
        return self.value


class NotApplicable:
    """*Not applicable*: no verdict at all (DESIGN.md section 1, "Verdicts").

    The algorithm cannot give what a property reads (no range graph, no parent field, ...), so
    the question is not asked: not held, not violated, and not inconclusive either (inconclusive
    is a question asked and not decided).  A row of the property matrix may carry it in place of
    a :class:`Verdict`; it is counted apart and never decides an exit code.  It has the
    attributes of a verdict that reports read (``value``, ``passed``), so it prints as ``n/a``.
    There is one: :data:`NOT_APPLICABLE`.

    >>> NOT_APPLICABLE.value, NOT_APPLICABLE.passed, str(NOT_APPLICABLE)
    ('n/a', False, 'n/a')
    """

    __slots__ = ()
    value = "n/a"
    passed = False
    _instance = None

    def __new__(cls):
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "NOT_APPLICABLE"

    def __str__(self) -> str:
        return self.value

    def __reduce__(self):
        return (NotApplicable, ())


#: The one :class:`NotApplicable`.
NOT_APPLICABLE = NotApplicable()


#: The three statuses a check's result carries (held / violated / inconclusive).
STATUSES = ("held", "violated", "inconclusive")


class ThreeValued:
    """Mixin of a result with a ``status`` among :data:`STATUSES`: ``held``, ``violated``, and
    truth only when held (inconclusive is never a pass).

    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class R(ThreeValued):
    ...     status: str
    >>> bool(R("inconclusive")), R("violated").violated
    (False, True)
    """

    __slots__ = ()

    @property
    def held(self) -> bool:
        return self.status == "held"

    @property
    def violated(self) -> bool:
        return self.status == "violated"

    def __bool__(self) -> bool:
        return self.held

    def _check_status(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status={self.status!r} must be held, violated or inconclusive")
