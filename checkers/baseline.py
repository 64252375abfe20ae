"""Verdict baselines: ``swarmproof verify --baseline FILE`` separates known findings from new ones.

A baseline is the property matrix of one ``verify`` run, kept in a file
(``swarmproof-baseline/1``, JSON, written atomically and deterministically by
``--update-baseline``)::

    {"format": "swarmproof-baseline/1",
     "gate": {"max_examples": 300, "robots": [3, 8], "seed": 0},
     "made_by": {"swarmproof": "0.1.0", "python": "3.11.7", "numpy": "2.3.5"},
     "readings": {"song2014": "1", "song2016": "1", ...},
     "rows": [{"section": "exploration", "subject": "song2014 n=3..8", "property": "tree_links",
               "algorithm": "song2014", "claim": "000 Lemma 7", "verdict": "violated",
               "signature": {"property": "tree_links", "size": 3,
                             "kind": "the link child # -> parent # broke"}}, ...]}

``gate`` holds the exploration parameters the rows were made with (the
explorer is bounded by example counts only, never by wall time, so a slow CI
runner gives the same verdicts); ``verify --baseline`` uses them.  A violated
row keeps a *signature* of its counterexample -- the property, the shrunk size
(robots) and the kind of message (numbers replaced by ``#``) -- so that a new
failure inside a row already known to be violated is reported.

``readings`` records the reading version (``Algorithm.reading``, bumped whenever an
algorithm's behaviour changes on purpose) of every algorithm the rows name, as the run used
it.  A baseline without the table was made before readings were versioned: every algorithm
in it is reading ``"1"``.  A row whose algorithm runs another reading now than the baseline
records is not compared (its verdicts are of another algorithm): it is ``reading``, and fails
the gate until the baseline is regenerated on purpose (``--update-baseline``).

How a row compares (:func:`compare`; the exit code of ``verify --baseline``):

============  ==========================================================  =====
outcome       meaning                                                     exit
============  ==========================================================  =====
same          as the baseline says (held or proved)                       0
known         violated, as the baseline says, with the same signature     0
regressed     held or proved in the baseline, violated now                1
changed       violated in both, but a different kind of failure           1
new           not in the baseline: judged by its claim (a claimed         1 / 3
              violated row 1, a claimed inconclusive row 3, else 0)
inconclusive  inconclusive now: a claimed row (never a pass, whatever    3
              the baseline), or any row the baseline has another verdict
              for (an unclaimed row inconclusive in both is ``same``)
weakened      proved in the baseline, only held now                       3
n/a           not applicable now (the algorithm cannot give what the      0 (1 with ``--strict``
              property needs: no verdict), any other verdict in the           when the baseline
              baseline; inconclusive then n/a is no regression                held a verdict)
improved      violated in the baseline, held or proved now                0 (1 with ``--strict``)
resized       violated in both, same kind, another counterexample size    0 (1 with ``--strict``)
reading       the baseline was made with another reading of the row's     1
              algorithm: not compared (update the baseline on purpose)
gone          in the baseline, in this run's scope, but not produced      warning (2 with ``--strict``)
============  ==========================================================  =====

A row not applicable in both is ``same``; a row n/a in the baseline that has a verdict now is
judged as a ``new`` row (by its claim).  n/a rows are written to the baseline as such
(``"verdict": "n/a"``).

Unclaimed rows (findings, ``*``) are compared like the others once they are
in the baseline: the baseline is what the user expects, claimed or not.

Examples
--------
>>> message_kind("the communication graph splits after step 11 into 2 components: [[0], [1, 2, 3]]")
'the communication graph splits after step # into # components'
>>> message_kind("step 344: the link child 2 -> parent 16 broke (distance 1.17 -> 1.21, range 1.2)")
'the link child # -> parent # broke'
>>> message_kind("robots 1 and 5 overlap in step 11: distance 0.1967 < 2r = 0.2 at 1.00 of the step")
'robots # and # overlap in step #'
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

from swarmproof.models.errors import InputFileError
from swarmproof.models.verdict import EXIT_INCONCLUSIVE, EXIT_OK, EXIT_VIOLATED, NOT_APPLICABLE, Verdict

__all__ = ["BASELINE_FORMAT", "Expected", "Baseline", "Change", "Comparison", "compare", "current_reading",
           "signature", "message_kind", "OUTCOMES"]

BASELINE_FORMAT = "swarmproof-baseline/1"

#: Every outcome of :func:`compare`, in the order the report lists them.
OUTCOMES = ("regressed", "changed", "reading", "new", "inconclusive", "weakened", "improved", "resized", "gone",
            "n/a", "known", "same")

_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
_RANK = {Verdict.VIOLATED: 0, Verdict.INCONCLUSIVE: 1, Verdict.HELD: 2, Verdict.PROVED: 3}


def message_kind(text: str) -> str:
    """The kind of a violation message: without a leading ``step N:``, its head (up to the first
    ``": "``, ``"; "`` or ``" ("``: the witness's figures), numbers replaced by ``#``, at most 120
    characters.  Two counterexamples of one kind differ only in numbers and witnesses."""
    text = re.sub(r"^\s*step \d+: ", "", str(text or ""))
    head = re.split(r": |; | \(", text, maxsplit=1)[0]
    return " ".join(_NUMBER.sub("#", head).split())[:120]


def signature(row) -> dict | None:
    """``{"property", "size", "kind"}`` of a violated row's counterexample, None for other rows.

    ``size`` is the number of robots of the (shrunk) counterexample of an
    exploration row, the number of robots of an algorithm row's runs, None
    for lemma and lattice rows; ``kind`` is :func:`message_kind` of the
    violation message (the row's detail when it has none).
    """
    if row.verdict is not Verdict.VIOLATED:
        return None
    data = row.data or {}
    size = data.get("counterexample_robots", data.get("robots"))
    if not isinstance(size, int) or isinstance(size, bool):
        size = None
    message = (data.get("violation") or {}).get("message") or row.detail
    return {"property": row.property, "size": size, "kind": message_kind(message)}


@dataclass(frozen=True)
class Expected:
    """One row of a baseline: what ``verify`` is expected to say of it."""

    section: str
    subject: str
    property: str
    verdict: Verdict          # or NOT_APPLICABLE
    claim: str | None = None
    algorithm: str | None = None
    signature: dict | None = field(default=None, compare=False)
    #: An exhaustive row's coverage (issue 33): ``{"complete", "bound"}``, recorded, not compared.
    exhaustive: dict | None = field(default=None, compare=False)

    @property
    def key(self) -> tuple[str, str, str]:
        return (self.section, self.subject, self.property)

    def to_json(self) -> dict[str, Any]:
        doc: dict[str, Any] = {"section": self.section, "subject": self.subject, "property": self.property,
                               "verdict": self.verdict.value, "claim": self.claim}
        if self.algorithm is not None:
            doc["algorithm"] = self.algorithm
        if self.signature is not None:
            doc["signature"] = dict(self.signature)
        if self.exhaustive is not None:
            doc["exhaustive"] = dict(self.exhaustive)
        return doc

    @classmethod
    def of_row(cls, row) -> "Expected":
        algo = (row.data or {}).get("algorithm")
        ex = (row.data or {}).get("exhaustive")
        cover = None if not isinstance(ex, dict) else {"complete": bool(ex.get("complete")), "bound": ex.get("bound")}
        return cls(row.section, row.subject, row.property, row.verdict, row.claim,
                   algo if isinstance(algo, str) else None, signature(row), cover)


def _key_text(key: tuple[str, str, str]) -> str:
    return f"{key[0]}: {key[1]} / {key[2]}"


@dataclass
class Baseline:
    """Expected verdicts by ``(section, subject, property)``, and the gate they were made with."""

    rows: dict[tuple[str, str, str], Expected]
    gate: dict[str, Any] = field(default_factory=dict)
    made_by: dict[str, str] = field(default_factory=dict)
    path: str | None = None
    #: algorithm -> the reading version its rows were made with; an algorithm the table does
    #: not name (a baseline from before readings were versioned) is reading "1"
    readings: dict[str, str] = field(default_factory=dict)

    @classmethod
    def from_rows(cls, rows: Iterable, gate: dict[str, Any]) -> "Baseline":
        from swarmproof.models.versions import tool_versions

        exp = [Expected.of_row(r) for r in rows]
        readings = {a: r for a in sorted({e.algorithm for e in exp if e.algorithm})
                    if (r := current_reading(a)) is not None}
        return cls({e.key: e for e in exp}, dict(gate), tool_versions(), readings=readings)

    def reading_of(self, algorithm: str) -> str:
        """The reading of ``algorithm`` the rows were made with (``"1"`` when not recorded)."""
        from swarmproof.models.versions import DEFAULT_READING

        return self.readings.get(algorithm, DEFAULT_READING)

    def merged(self, newer: "Baseline", in_scope: Callable[[Expected], bool]) -> "Baseline":
        """``newer``'s rows, plus this baseline's rows outside the run's scope (kept as they were,
        with the readings they were made with)."""
        rows = {k: e for k, e in self.rows.items() if not in_scope(e)}
        kept = {e.algorithm for e in rows.values() if e.algorithm}
        readings = {a: self.reading_of(a) for a in kept}
        rows.update(newer.rows)
        readings.update(newer.readings)
        return Baseline(rows, dict(newer.gate), dict(newer.made_by), self.path, readings)

    def to_json(self) -> dict[str, Any]:
        return {"format": BASELINE_FORMAT, "gate": self.gate, "made_by": self.made_by,
                "readings": {a: self.readings[a] for a in sorted(self.readings)},
                "rows": [self.rows[k].to_json() for k in sorted(self.rows)]}

    def save(self, path: str | os.PathLike) -> str:
        """Write atomically (deterministic bytes: sorted keys and rows)."""
        from swarmproof.models.fileio import atomic_write_json

        return atomic_write_json(path, self.to_json())

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Baseline":
        """Read and check a baseline file.

        Raises
        ------
        InputFileError
            Missing or unreadable file, not JSON (with the line), another
            format or version, a missing or mistyped field (named), a
            duplicated row.
        """
        name = os.fspath(path)
        fix_new = "write one with `swarmproof verify --baseline FILE --update-baseline`"
        try:
            with open(name, encoding="utf-8") as fh:
                text = fh.read()
        except FileNotFoundError:
            raise InputFileError(f"baseline file={name!r} does not exist", file=name, fix=fix_new) from None
        except OSError as exc:
            raise InputFileError(f"cannot read baseline file={name!r} ({exc.strerror})", file=name,
                                 fix="give the path of a readable swarmproof-baseline/1 file") from None
        except UnicodeDecodeError as exc:
            raise InputFileError(f"the baseline is not UTF-8 text (byte {exc.start}: {exc.reason})", file=name,
                                 fix=fix_new) from None
        try:
            doc = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputFileError(f"the baseline is not JSON ({exc.msg})", file=name, line=exc.lineno,
                                 fix="restore it from version control, or delete it and " + fix_new) from None
        return cls.from_json(doc, file=name)

    @classmethod
    def from_json(cls, doc: Any, *, file: str | None = None) -> "Baseline":
        def err(fld: str, msg: str, fix: str | None = None) -> InputFileError:
            return InputFileError(msg, file=file, field=fld,
                                  fix=fix or "restore the file from version control, or delete it and write a new "
                                             "one with `swarmproof verify --baseline FILE --update-baseline`")

        if not isinstance(doc, dict):
            raise err("format", f"the baseline is a JSON {type(doc).__name__}, not an object")
        fmt = doc.get("format")
        if fmt != BASELINE_FORMAT:
            raise err("format", f"format={fmt!r} is not {BASELINE_FORMAT!r}",
                      fix=f"this swarmproof reads {BASELINE_FORMAT}; delete the file and write a new one "
                          "with `swarmproof verify --baseline FILE --update-baseline`")
        gate = doc.get("gate", {})
        if not isinstance(gate, dict):
            raise err("gate", f"gate={gate!r} is not an object")
        for k, typ in (("max_examples", int), ("seed", int)):
            if k in gate and (not isinstance(gate[k], typ) or isinstance(gate[k], bool)):
                raise err(f"gate.{k}", f"gate.{k}={gate[k]!r} is not an integer")
        if "robots" in gate and not (isinstance(gate["robots"], list) and len(gate["robots"]) == 2
                                     and all(isinstance(x, int) and not isinstance(x, bool) for x in gate["robots"])):
            raise err("gate.robots", f"gate.robots={gate['robots']!r} is not [MIN, MAX]")
        made_by = doc.get("made_by", {})
        if not isinstance(made_by, dict):
            raise err("made_by", f"made_by={made_by!r} is not an object")
        readings = doc.get("readings", {})
        if not isinstance(readings, dict):
            raise err("readings", f"readings={readings!r} is not an object (algorithm -> reading)")
        for a, r in readings.items():
            if not isinstance(r, str) or not r.strip():
                raise err(f"readings.{a}", f"readings.{a}={r!r} is not a reading (a non-empty string, e.g. \"1\")")
        rows_doc = doc.get("rows")
        if not isinstance(rows_doc, list):
            raise err("rows", f"rows={rows_doc!r} is not a list")
        rows: dict[tuple[str, str, str], Expected] = {}
        for i, r in enumerate(rows_doc):
            where = f"rows[{i}]"
            if not isinstance(r, dict):
                raise err(where, f"{where}={r!r} is not an object")
            for k in ("section", "subject", "property", "verdict"):
                if not isinstance(r.get(k), str):
                    raise err(f"{where}.{k}", f"{where}.{k}={r.get(k)!r} is not a string")
            try:
                verdict = NOT_APPLICABLE if r["verdict"] == NOT_APPLICABLE.value else Verdict(r["verdict"])
            except ValueError:
                raise err(f"{where}.verdict", f"{where}.verdict={r['verdict']!r} is not one of "
                                              f"{[v.value for v in Verdict] + [NOT_APPLICABLE.value]}") from None
            for k in ("claim", "algorithm"):
                if r.get(k) is not None and not isinstance(r[k], str):
                    raise err(f"{where}.{k}", f"{where}.{k}={r[k]!r} is not a string or null")
            sig = r.get("signature")
            if sig is not None and not (isinstance(sig, dict) and isinstance(sig.get("kind"), str)):
                raise err(f"{where}.signature", f"{where}.signature={sig!r} is not "
                                                "{property, size, kind}")
            ex = r.get("exhaustive")
            if ex is not None and not (isinstance(ex, dict) and isinstance(ex.get("complete"), bool)):
                raise err(f"{where}.exhaustive", f"{where}.exhaustive={ex!r} is not {{complete, bound}}")
            e = Expected(r["section"], r["subject"], r["property"], verdict, r.get("claim"), r.get("algorithm"),
                         sig, ex)
            if e.key in rows:
                raise err(where, f"{where} repeats the row {_key_text(e.key)!r}",
                          fix="keep one row per section, subject and property")
            rows[e.key] = e
        return cls(rows, gate, {str(k): str(v) for k, v in made_by.items()}, file, dict(readings))


@dataclass(frozen=True)
class Change:
    """How one row compares with the baseline."""

    outcome: str
    key: tuple[str, str, str]
    verdict: Verdict | None        # now (None: gone)
    expected: Verdict | None       # in the baseline (None: new)
    claim: str | None
    note: str = ""
    row: Any = field(default=None, compare=False)

    def to_json(self) -> dict[str, Any]:
        return {"section": self.key[0], "subject": self.key[1], "property": self.key[2],
                "outcome": self.outcome, "verdict": None if self.verdict is None else self.verdict.value,
                "expected": None if self.expected is None else self.expected.value, "claim": self.claim,
                "note": self.note}


def _sig_text(sig: dict | None) -> str:
    if not sig:
        return "no signature"
    size = "" if sig.get("size") is None else f"{sig['size']} robots, "
    return f"{size}{sig.get('kind', '')!r}"


def current_reading(algorithm: str) -> str | None:
    """The reading ``algorithm`` (a registry name or ``module:qualname``) runs in this swarmproof;
    None when it cannot be resolved here (its rows are then compared as before)."""
    from swarmproof.checkers.algorithm_spec import resolve_algorithm
    from swarmproof.models.errors import UsageError

    try:
        return resolve_algorithm(algorithm).reading
    except UsageError:
        return None


def _reading_change(row, exp: Expected, baseline: "Baseline", readings: dict) -> Change | None:
    """A ``reading`` change when ``row``'s algorithm runs another reading than the baseline's rows
    of it were made with; None otherwise."""
    algo = (row.data or {}).get("algorithm") if row is not None else None
    algo = algo if isinstance(algo, str) else exp.algorithm
    if not algo:
        return None
    if algo not in readings:
        readings[algo] = current_reading(algo)
    now_reading, then_reading = readings[algo], baseline.reading_of(algo)
    if now_reading is None or now_reading == then_reading:
        return None
    return Change("reading", exp.key, row.verdict, exp.verdict, row.claim,
                  f"the baseline was made with reading {then_reading!r} of {algo}, this run uses reading "
                  f"{now_reading!r} (baseline {exp.verdict.value}, now {row.verdict.value}): not compared; "
                  "regenerate the baseline on purpose (--update-baseline) and give the reason for each "
                  "changed row", row)


def _compare_row(row, exp: Expected | None) -> Change:
    now = row.verdict
    if exp is not None and now is NOT_APPLICABLE:
        if exp.verdict is NOT_APPLICABLE:
            return Change("same", exp.key, now, exp.verdict, row.claim, "", row)
        return Change("n/a", exp.key, now, exp.verdict, row.claim,
                      f"{exp.verdict.value} in the baseline, not applicable now ({row.detail})", row)
    if exp is not None and exp.verdict is NOT_APPLICABLE:
        change = _compare_row(row, None)
        return Change(change.outcome, change.key, now, exp.verdict, row.claim,
                      f"n/a in the baseline, {now.value} now: judged by its claim", row)
    if exp is None and now is NOT_APPLICABLE:
        return Change("new", (row.section, row.subject, row.property), now, None, row.claim,
                      "not in the baseline; not applicable", row)
    if exp is None:
        if not row.claimed:
            note = "not in the baseline; not claimed (a finding)" if now is Verdict.VIOLATED else "not in the baseline"
        else:
            note = "not in the baseline: judged by its claim"
        return Change("new", (row.section, row.subject, row.property), now, None, row.claim, note, row)
    base = exp.verdict
    key = exp.key
    if now is Verdict.INCONCLUSIVE:
        if base is now and not row.claimed:
            return Change("same", key, now, base, row.claim, "", row)   # not claimed: not counted, as without a baseline
        note = ("a claimed row, inconclusive in the baseline too: never a pass" if base is now
                else f"{base.value} in the baseline, inconclusive now")
        return Change("inconclusive", key, now, base, row.claim, note, row)
    if now is Verdict.VIOLATED:
        if base is not Verdict.VIOLATED:
            return Change("regressed", key, now, base, row.claim, f"{base.value} in the baseline, violated now", row)
        sig_now, sig_then = signature(row), exp.signature
        if sig_then is None or sig_now is None:
            return Change("known", key, now, base, row.claim, "violated, as the baseline says", row)
        if sig_now.get("kind") != sig_then.get("kind") or sig_now.get("property") != sig_then.get("property"):
            return Change("changed", key, now, base, row.claim,
                          f"a new failure in a known-violated row: baseline {_sig_text(sig_then)}, "
                          f"now {_sig_text(sig_now)}", row)
        if sig_now.get("size") != sig_then.get("size"):
            return Change("resized", key, now, base, row.claim,
                          f"the same kind of failure with another counterexample size: baseline "
                          f"{sig_then.get('size')} robots, now {sig_now.get('size')}", row)
        return Change("known", key, now, base, row.claim, "violated, as the baseline says", row)
    # held or proved now
    if base is Verdict.VIOLATED or base is Verdict.INCONCLUSIVE:
        return Change("improved", key, now, base, row.claim, f"{base.value} in the baseline, {now.value} now", row)
    if _RANK[now] < _RANK[base]:
        return Change("weakened", key, now, base, row.claim, f"{base.value} in the baseline, only {now.value} now", row)
    return Change("same", key, now, base, row.claim, "", row)


@dataclass
class Comparison:
    """Every row of a report against a baseline, and the rows of the baseline that are gone."""

    changes: list[Change]
    baseline: Baseline
    strict: bool = False
    _by_key: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._by_key = {c.key: c for c in self.changes}

    def of(self, outcome: str) -> list[Change]:
        return [c for c in self.changes if c.outcome == outcome]

    @property
    def new_violations(self) -> list[Change]:
        return [c for c in self.of("new") if c.verdict is Verdict.VIOLATED and c.claim is not None]

    @property
    def new_inconclusive(self) -> list[Change]:
        return [c for c in self.of("new") if c.verdict is Verdict.INCONCLUSIVE and c.claim is not None]

    def fails(self, c: Change) -> bool:
        """Whether ``c`` fails the gate (exit 1): a regression, a new kind of failure in a
        known-violated row, a new claimed violation; with ``strict`` an improvement or a resize."""
        if c.outcome in ("regressed", "changed", "reading"):
            return True
        if c.outcome == "new":
            return c.verdict is Verdict.VIOLATED and c.claim is not None
        if c.outcome == "n/a":       # a verdict in the baseline that is no longer asked for
            return self.strict and c.expected is not Verdict.INCONCLUSIVE
        return self.strict and c.outcome in ("improved", "resized")

    def undecided(self, c: Change) -> bool:
        """Whether ``c`` makes the gate inconclusive (exit 3, when nothing fails)."""
        if c.outcome in ("inconclusive", "weakened"):
            return True
        return c.outcome == "new" and c.verdict is Verdict.INCONCLUSIVE and c.claim is not None

    @property
    def failing(self) -> list[Change]:
        """The changes that make the gate fail (exit 1)."""
        return [c for c in self.changes if self.fails(c)]

    @property
    def exit_code(self) -> int:
        if self.failing:
            return EXIT_VIOLATED
        if any(self.undecided(c) for c in self.changes):
            return EXIT_INCONCLUSIVE
        return EXIT_OK

    def change_of(self, key) -> Change | None:
        """The change of the row ``(section, subject, property)``, None when there is none."""
        return self._by_key.get(tuple(key))

    def outcome_of(self, key) -> str | None:
        c = self.change_of(key)
        return None if c is None else c.outcome

    def counts(self) -> dict[str, int]:
        out = {o: len(self.of(o)) for o in OUTCOMES}
        out["new_violations"] = len(self.new_violations)
        out["held"] = sum(c.verdict is not None and c.verdict.passed for c in self.changes)
        out["not_applicable"] = sum(c.verdict is NOT_APPLICABLE for c in self.changes)
        return out

    def summary_line(self) -> str:
        """The one line a person reads first."""
        n = self.counts()
        regress = n["regressed"] + n["changed"] + n["new_violations"]
        findings = n["known"] + n["resized"] + sum(c.verdict is Verdict.VIOLATED and c.claim is None
                                                   for c in self.of("new"))
        inconc = n["inconclusive"] + n["weakened"] + len(self.new_inconclusive)
        status = {EXIT_OK: "PASS", EXIT_VIOLATED: "FAIL", EXIT_INCONCLUSIVE: "INCONCLUSIVE"}[self.exit_code]
        parts = [f"{regress} regression" + ("" if regress == 1 else "s"),
                 f"{findings} known finding" + ("" if findings == 1 else "s"),
                 f"{n['improved']} improvement" + ("" if n["improved"] == 1 else "s"),
                 f"{n['held']} held"]
        tail = []
        if inconc:
            tail.append(f"{inconc} inconclusive")
        if n["not_applicable"]:
            tail.append(f"{n['not_applicable']} n/a (not applicable)")
        if n["gone"]:
            tail.append(f"{n['gone']} baseline row" + ("" if n["gone"] == 1 else "s") + " gone")
        if n["reading"]:
            tail.append(f"{n['reading']} row" + ("" if n["reading"] == 1 else "s")
                        + " made with another reading (not compared)")
        where = self.baseline.path or "the baseline"
        return (f"verify: {status}: " + ", ".join(parts) + (f"; {', '.join(tail)}" if tail else "")
                + f" (against {where})")

    def lines(self) -> list[str]:
        """The human block before the summary line: what differs from the baseline, then the
        known findings with their citations."""
        out: list[str] = []
        titles = [("regressed", "REGRESSED (held or proved in the baseline, violated now)"),
                  ("changed", "CHANGED (a new failure in a known-violated row)"),
                  ("reading", "READING CHANGED (the baseline was made with another reading of the algorithm: "
                              "not compared; update the baseline on purpose: --update-baseline)"),
                  ("new", "NEW (not in the baseline)"),
                  ("inconclusive", "INCONCLUSIVE (never a pass)"),
                  ("weakened", "WEAKENED (proved in the baseline, only held now)"),
                  ("improved", "IMPROVED (update the baseline on purpose: --update-baseline)"),
                  ("resized", "RESIZED (same failure, another counterexample size)"),
                  ("gone", "GONE (in the baseline, not produced by this run)"),
                  ("n/a", "NOT APPLICABLE NOW (the baseline had a verdict; update it: --update-baseline)"),
                  ("known", "known findings (violated, as the baseline says)")]
        for outcome, title in titles:
            group = self.of(outcome)
            if outcome == "new":
                group = [c for c in group if c.verdict is not Verdict.HELD and c.verdict is not Verdict.PROVED
                         and c.verdict is not NOT_APPLICABLE]
            if not group:
                continue
            out.append(f"-- {title}")
            for c in group:
                cite = f" [{c.claim}]" if c.claim else " [not claimed]"
                verdict = "" if c.verdict is None else c.verdict.value
                out.append(f"  {_key_text(c.key)}: {verdict}{cite}" + (f" -- {c.note}" if c.note else ""))
                how = _how_to_repeat(c.row)
                if how and c.verdict is Verdict.VIOLATED:
                    out.append(f"      {how}")
        return out

    def to_json(self) -> dict[str, Any]:
        return {"file": self.baseline.path, "format": BASELINE_FORMAT, "made_by": self.baseline.made_by,
                "readings": dict(self.baseline.readings),
                "gate": self.baseline.gate, "strict": self.strict, "exit_code": self.exit_code,
                "counts": self.counts(),
                "changes": [c.to_json() for c in self.changes if c.outcome not in ("same",)]}


def _how_to_repeat(row) -> str:
    """``replay: swarmproof replay FILE`` or ``repeat: COMMAND`` of a violated row, else ''."""
    if row is None:
        return ""
    data = row.data or {}
    if data.get("counterexample"):
        return f"replay: swarmproof replay {data['counterexample']}"
    if data.get("reproduce"):
        return f"repeat: {data['reproduce']}"
    return ""


def compare(rows: Iterable, baseline: Baseline, *, in_scope: Callable[[Expected], bool] = lambda e: True,
            strict: bool = False) -> Comparison:
    """Compare a report's rows with ``baseline`` (see the module docstring for the outcomes).

    ``in_scope(expected)`` says whether this run would have produced a
    baseline row (its section, algorithm and property ran); a row in scope
    that the run did not produce is ``gone``; rows out of scope are ignored.
    """
    changes: list[Change] = []
    seen = set()
    readings: dict = {}
    for row in rows:
        key = (row.section, row.subject, row.property)
        seen.add(key)
        exp = baseline.rows.get(key)
        reread = None if exp is None else _reading_change(row, exp, baseline, readings)
        changes.append(reread if reread is not None else _compare_row(row, exp))
    for key, exp in baseline.rows.items():
        if key not in seen and in_scope(exp):
            changes.append(Change("gone", key, None, exp.verdict, exp.claim,
                                  f"{exp.verdict.value} in the baseline; this run has no such row "
                                  "(renamed or removed: --update-baseline drops it)"))
    return Comparison(changes, baseline, strict)

