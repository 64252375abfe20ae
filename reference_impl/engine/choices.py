"""Choice points: every nondeterministic decision of a run's fault model in one place (issue 33).

A run's fault model decides which robots act in a step, each delivery's fate (lost, late,
twice, in which order) and which robot crashes when.  :class:`Choices` makes each of those
decisions.  Without a chooser it draws exactly as the engine always has -- the fault model's
hooks and the fault generator, in the same order -- so a seeded run is bit-identical to one
made before choice points existed (``tests/reference_impl/test_trace_identity.py`` pins the
traces).  With a chooser (:class:`Chooser`), the decisions of the kinds it names
(:data:`CHOICE_KINDS`) come from ``chooser.choose(kind, options, default, at)`` instead: the
exhaustive checker (:mod:`swarmproof.checkers.exhaustive`) enumerates them by re-execution,
and a counterexample's recorded choices replay them (:class:`RecordedChoices`).

Choice kinds (``at`` says where the decision is made):

``activate``
    Which of the present robots act in step ``t`` (``at = (t,)``): the non-empty subsets of
    them, largest first; default every one of them.  With asynchronous clocks, of the robots
    whose clock ticks.  A robot that does not act neither decides nor broadcasts.
``loss``
    Whether a delivery is lost (``at = (t, sender, receiver)``; ``(False, True)``, default
    False); after the fault model's own ``drop_message``.
``delay``
    How many steps late a delivery arrives (``0 .. max_delay``, default 0).
``duplicate``
    How many copies arrive (``(1, 2)``, default 1).
``reorder``
    The order a robot reads its deliveries due in a step (``at = (t, receiver)``): the
    permutations of them, default the sending order (at most :data:`MAX_REORDERED` deliveries
    are permuted; the rest keep their order).
``crash``
    Which robot crashes at the start of step ``t`` (``at = (t,)``): ``None`` (default) or one
    of the present robots' IDs, while the chooser's ``max_crashes`` is not spent and more
    than one robot is present.
``clock_phase``
    Asynchronous clocks (``RobotModel.clocks="async"``): each start robot's clock phase, chosen
    before step 0 (``at = (robot,)``).  A phase is continuous, but within the run's step cap it
    makes only finitely many behaviours (the steps the robot decides and broadcasts in):
    :func:`phase_classes` gives one phase per behaviour, and the options are the seeded phase
    (default) and one phase of each other behaviour.  Clock rates stay the seeded ones.

The engine also asks the chooser, after each step, whether to go on
(:meth:`Chooser.after_step`, with a digest of the run's whole state: :func:`state_digest`).
"""

from __future__ import annotations

import hashlib
import itertools
import struct
import types
from typing import Sequence

import numpy as np

from swarmproof.models.errors import UsageError

__all__ = ["CHOICE_KINDS", "MAX_ACTIVATION_ROBOTS", "MAX_REORDERED", "Chooser", "Choices", "RecordedChoices",
           "activation_options", "state_digest"]

#: The decisions a chooser can make (module docstring).
CHOICE_KINDS = ("activate", "loss", "delay", "duplicate", "reorder", "crash", "clock_phase")
#: Activation choices enumerate 2^n - 1 subsets: refused above this many acting robots.
MAX_ACTIVATION_ROBOTS = 10
#: Reorder choices permute at most this many deliveries of one robot in one step (5! = 120).
MAX_REORDERED = 5

#: The kinds that route deliveries through the receivers' queues (late delivery).
_LATE_KINDS = frozenset({"delay", "duplicate", "reorder"})


class Chooser:
    """What the engine asks when a decision is the chooser's (subclass it).

    Attributes
    ----------
    kinds : frozenset of str
        The kinds it decides (:data:`CHOICE_KINDS`); the others are drawn as without a chooser.
    max_delay : int
        The largest delay a ``delay`` choice offers (steps).
    max_crashes : int
        How many ``crash`` choices may pick a robot in one run.
    """

    kinds: frozenset = frozenset()
    max_delay: int = 1
    max_crashes: int = 1

    def choose(self, kind: str, options: Sequence, default, at: tuple = ()):
        """One of ``options`` (``default`` is among them) for the decision ``kind`` at ``at``."""
        raise NotImplementedError

    def after_step(self, t: int, digest) -> bool:
        """Called after every step ``t`` but the last with ``digest()``, the run's state digest
        (computed only when called; ``digest(symmetric=True)`` up to relabelling anonymous robots);
        True ends the run there (status ``"pruned"``)."""
        return False

    def describe(self) -> dict:
        """What the run's ``trace.meta["choices"]`` records."""
        return {"kinds": sorted(self.kinds), "max_delay": int(self.max_delay), "max_crashes": int(self.max_crashes)}


def check_chooser(chooser) -> None:
    """Refuse a chooser that names an unknown kind or a bound that is not an integer >= 0."""
    kinds = getattr(chooser, "kinds", None)
    if not callable(getattr(chooser, "choose", None)) or kinds is None:
        raise UsageError(f"chooser={chooser!r} has no choose(kind, options, default, at) and kinds",
                         fix="subclass swarmproof.reference_impl.engine.choices.Chooser")
    bad = sorted(set(kinds) - set(CHOICE_KINDS))
    if bad:
        raise UsageError(f"chooser kinds={sorted(kinds)!r}: unknown {bad!r}", fix=f"use some of {list(CHOICE_KINDS)}")
    for name in ("max_delay", "max_crashes"):
        v = getattr(chooser, name, 0)
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0:
            raise UsageError(f"chooser {name}={v!r} must be an integer >= 0")


def activation_options(ids: Sequence[int]) -> list[tuple]:
    """The non-empty subsets of ``ids`` (sorted tuples), largest first, then in lexicographic
    order of positions: the default (every robot) comes first.

    >>> activation_options([3, 5, 8])
    [(3, 5, 8), (3, 5), (3, 8), (5, 8), (3,), (5,), (8,)]
    """
    ids = sorted(int(i) for i in ids)
    if len(ids) > MAX_ACTIVATION_ROBOTS:
        raise UsageError(f"activation choices over n={len(ids)} robots ({2 ** len(ids) - 1} subsets a step)",
                         fix=f"enumerate activation with at most {MAX_ACTIVATION_ROBOTS} robots, or drop the "
                             "activate kind")
    out = []
    for size in range(len(ids), 0, -1):
        out.extend(itertools.combinations(ids, size))
    return out


def _every_robot(t, ids, rng):
    """A schedule that lets every robot act (stands for the chooser's activation choices)."""
    return np.ones(len(ids), dtype=bool)


class Choices:
    """The run's decisions (module docstring): drawn as always, or the chooser's.

    Parameters
    ----------
    faults : FaultModel
    rng : numpy.random.Generator
        The fault generator (``SeedSequence(seed, spawn_key=(1,))``).
    chooser : Chooser or None
    """

    def __init__(self, faults, rng, chooser=None) -> None:
        self.faults, self.rng, self.chooser = faults, rng, chooser
        self.kinds = frozenset(chooser.kinds) if chooser is not None else frozenset()
        kinds = self.kinds
        self.max_delay = int(chooser.max_delay) if "delay" in kinds else int(faults.message_delay)
        self.crashes_left = int(chooser.max_crashes) if "crash" in kinds else 0
        #: deliveries go through the loss test / the receivers' queues
        self.drops = faults.drops_messages or "loss" in kinds
        self.late = faults.late_messages or bool(kinds & _LATE_KINDS)
        self.dup_p = float(faults.message_duplication)

    def broken_assumptions(self, model) -> list[str]:
        """The robot-model assumptions the chooser's kinds break (as the fault model's own
        hooks of those kinds would: :meth:`.faults.FaultModel.broken_model_assumptions`)."""
        kinds = self.kinds
        if not kinds:
            return []
        from dataclasses import replace

        like = replace(self.faults,
                       schedule=_every_robot if "activate" in kinds else self.faults.schedule,
                       crashes={0: [0]} if "crash" in kinds and self.crashes_left else self.faults.crashes,
                       message_loss=1.0 if "loss" in kinds else self.faults.message_loss,
                       message_delay=self.max_delay if "delay" in kinds else self.faults.message_delay,
                       message_duplication=1.0 if "duplicate" in kinds else self.faults.message_duplication,
                       message_reorder=True if "reorder" in kinds else self.faults.message_reorder)
        return like.broken_model_assumptions(model)

    # -- the decisions, each drawn exactly as before unless its kind is the chooser's --

    def activation(self, t: int, ids: np.ndarray) -> np.ndarray | None:
        """Who acts in step ``t`` among the present robots ``ids`` (a boolean mask), or None when
        every one of them acts."""
        if "activate" in self.kinds:
            return self._chosen_subset(t, ids)
        sched = self.faults.schedule
        if sched is None:
            return None
        act = np.asarray(sched(t, ids.copy(), self.rng), dtype=bool)
        if act.shape != (len(ids),):
            raise UsageError(f"faults.schedule returned shape={act.shape!r}, expected ({len(ids)},)")
        return act

    def ticking(self, t: int, ids: np.ndarray, ticks: np.ndarray) -> np.ndarray:
        """Asynchronous clocks with the ``activate`` kind: which of the robots whose clock ticks
        (``ticks``) act (the chooser picks among them)."""
        if not ticks.any():
            return ticks
        return ticks & np.isin(ids, ids[ticks][self._chosen_subset(t, ids[ticks])])

    def _chosen_subset(self, t: int, ids: np.ndarray) -> np.ndarray:
        """The chooser's ``activate`` decision among ``ids``: a boolean mask over them."""
        opts = activation_options(ids.tolist())
        pick = self.chooser.choose("activate", opts, opts[0], (int(t),))
        return np.isin(ids, np.asarray(pick, dtype=np.int64))

    def lost(self, t: int, from_id, to_id) -> bool:
        """Whether the delivery from ``from_id`` to ``to_id`` sent in step ``t`` is lost: the fault
        model's ``drop_message`` hook, then ``message_loss`` (or the chooser's ``loss``)."""
        faults = self.faults
        if faults.drop_message is not None and faults.drop_message(t, from_id, to_id, self.rng):
            return True
        if "loss" in self.kinds:
            return bool(self.chooser.choose("loss", (False, True), False, (int(t), int(from_id), int(to_id))))
        return faults.message_loss > 0 and self.rng.random() < faults.message_loss

    def delay(self, t: int, from_id, to_id) -> int:
        """How many steps late the delivery arrives."""
        if "delay" in self.kinds:
            if not self.max_delay:
                return 0
            return int(self.chooser.choose("delay", tuple(range(self.max_delay + 1)), 0,
                                           (int(t), int(from_id), int(to_id))))
        return int(self.rng.integers(0, self.max_delay + 1)) if self.max_delay else 0

    def copies(self, t: int, from_id, to_id) -> int:
        """How many copies of the delivery arrive (1 or 2)."""
        if "duplicate" in self.kinds:
            return int(self.chooser.choose("duplicate", (1, 2), 1, (int(t), int(from_id), int(to_id))))
        return 2 if self.dup_p > 0 and self.rng.random() < self.dup_p else 1

    def order(self, t: int, to_id, n: int) -> list[int] | None:
        """The order of ``n > 1`` deliveries due to ``to_id`` in step ``t`` (a permutation of
        ``range(n)``), or None to keep the sending order."""
        if "reorder" in self.kinds:
            head = min(n, MAX_REORDERED)
            opts = list(itertools.permutations(range(head)))
            pick = self.chooser.choose("reorder", opts, opts[0], (int(t), int(to_id)))
            return list(pick) + list(range(head, n))
        if self.faults.message_reorder:
            return self.rng.permutation(n).tolist()
        return None

    def clock_phases(self, clocks, steps: int, ids: Sequence[int]) -> None:
        """``clock_phase`` choices: each start robot's phase (changed in ``clocks.phase``)."""
        if "clock_phase" not in self.kinds or not hasattr(clocks, "phase"):
            return
        for k, rid in enumerate(ids):
            opts = phase_classes(float(clocks.phase[k]), float(clocks.rate[k]), float(clocks.every), int(steps))
            clocks.phase[k] = float(self.chooser.choose("clock_phase", tuple(opts), opts[0], (int(rid),)))

    def crashed(self, t: int, ids: np.ndarray, present: np.ndarray) -> tuple:
        """The robots that crash at the start of step ``t``: the fault model's ``crashes[t]``,
        then the chooser's ``crash`` pick among the present robots (``ids[present]``)."""
        out = tuple(self.faults.crashes.get(t, ()))
        if self.crashes_left > 0:
            gone = {int(x) for x in out}
            alive = [int(i) for i in ids[present].tolist() if int(i) not in gone]
            if len(alive) > 1:
                opts = (None, *alive)
                pick = self.chooser.choose("crash", opts, None, (int(t),))
                if pick is not None:
                    self.crashes_left -= 1
                    out = out + (int(pick),)
        return out


def _clock_signature(phase: float, rate: float, every: float, steps: int) -> bytes:
    """The steps ``0 .. steps - 1`` a clock of this phase and rate decides and broadcasts in, with
    :meth:`.clocks.AsyncClocks.ticks`' own arithmetic."""
    t = np.arange(steps, dtype=float)
    tau0 = phase + rate * t
    tau1 = tau0 + rate
    decide = np.floor(tau1) > np.floor(tau0)
    bcast = np.floor((tau1 + 0.5) / every) > np.floor((tau0 + 0.5) / every)
    return np.packbits(decide).tobytes() + b"|" + np.packbits(bcast).tobytes()


def phase_classes(phase: float, rate: float, every: float, steps: int) -> list[float]:
    """``phase`` first, then one phase of every other behaviour a clock of this ``rate`` can have
    within ``steps`` steps (which steps it decides and broadcasts in): the phases in [0, 1) where
    the behaviour changes are where ``phase + rate t`` or ``phase + rate t + 1/2`` meets an integer
    or a broadcast instant; between two of them the behaviour is one (the midpoint stands for it).

    >>> phase_classes(0.3, 1.0, 2.0, 10)      # rate 1, a broadcast every 2: even or odd steps
    [0.3, 0.75]
    >>> phase_classes(0.1, 0.5, 1.0, 8)       # rate 1/2: it decides every other step
    [0.1, 0.75]
    """
    cuts = {0.0, 1.0}
    top = rate * (steps + 1) + 2.0
    for t in range(steps + 1):
        cuts.add(float((-rate * t) % 1.0))
        for j in range(int(top / every) + 2):
            cuts.add(float((j * every - 0.5 - rate * t) % 1.0))
    edges = sorted(cuts)
    seen = {_clock_signature(phase, rate, every, steps)}
    out = [float(phase)]
    for a, b in zip(edges, edges[1:]):
        if b - a <= 1e-12:
            continue
        mid = (a + b) / 2.0
        sig = _clock_signature(mid, rate, every, steps)
        if sig not in seen:
            seen.add(sig)
            out.append(mid)
    return out


def deterministic_from(deviations) -> int:
    """The first recorded state from which a run is the default continuation of a state with no
    trace of its non-default decisions left outside the robots' poses and states: two steps past
    the step of the last decision (a robot left out at step s broadcast nothing in s, which its
    neighbours hear, or not, in s + 1), plus a late delivery's delay (in flight until it is due);
    ``clock_phase`` is chosen before step 0; 0 with no deviation.  Oscillation's cycle rule
    compares poses and states only, so it starts there.

    >>> deterministic_from([{"kind": "loss", "at": [3, 0, 1]}, {"kind": "activate", "at": [7]}])
    9
    >>> deterministic_from([{"kind": "delay", "at": [7, 0, 1], "option": 3}])
    12
    >>> deterministic_from([{"kind": "clock_phase", "at": [4]}]), deterministic_from([])
    (0, 0)
    """
    last = 0
    for d in deviations:
        at = list(d.get("at") or [])
        if d.get("kind") != "clock_phase" and at:
            late = int(d.get("option") or 0) if d.get("kind") == "delay" else 0
            last = max(last, int(at[0]) + 2 + late)
    return last


class RecordedChoices(Chooser):
    """A chooser that makes a recorded sequence of decisions again (a counterexample's
    ``choices``: :func:`swarmproof.checkers.exhaustive` writes them): at the ``index``-th
    decision the recorded option, elsewhere the default.

    A decision whose kind or options differ from the recording means the run is not the one
    recorded: :attr:`diverged` names the first such decision (replay reports it).

    >>> rc = RecordedChoices(["loss"], [{"index": 1, "kind": "loss", "option": True}])
    >>> [rc.choose("loss", (False, True), False, (0, 1, 2)) for _ in range(3)], rc.diverged
    ([False, True, False], None)
    """

    def __init__(self, kinds: Sequence[str], deviations: Sequence[dict], *, max_delay: int = 1,
                 max_crashes: int = 1) -> None:
        self.kinds = frozenset(kinds)
        self.max_delay, self.max_crashes = int(max_delay), int(max_crashes)
        self.at_index = {int(d["index"]): d for d in deviations}
        self.n = 0
        self.diverged: str | None = None

    def describe(self) -> dict:
        return {**super().describe(), "deterministic_from": deterministic_from(self.at_index.values())}

    def choose(self, kind, options, default, at=()):
        i = self.n
        self.n += 1
        d = self.at_index.get(i)
        if d is None:
            return default
        want = d.get("option")
        want = tuple(want) if isinstance(want, list) else want
        recorded_at = d.get("at")
        why = None
        if d.get("kind") != kind or want not in options:
            why = f"the recording has {d.get('kind')} option {d.get('option')!r}"
        elif recorded_at is not None and list(recorded_at) != [int(x) for x in at]:
            why = f"the recording places it at {list(recorded_at)}"
        elif want == default:
            why = f"the recording lists the default {d.get('option')!r} as a deviation"
        if why is not None:
            if self.diverged is None:
                self.diverged = f"decision {i} is {kind} at {list(at)}, {why}"
            return default
        return want

    def check_end(self, choice_points=None) -> str | None:
        """After the run: :attr:`diverged`, else why the recording does not fit the run (a recorded
        decision the run never reached, another count of decisions), else None."""
        if self.diverged is not None:
            return self.diverged
        beyond = [i for i in self.at_index if i >= self.n]
        if beyond:
            return f"the run made {self.n} decisions, the recording has a deviation at decision {beyond[0]}"
        if choice_points is not None and int(choice_points) != self.n:
            return f"the run made {self.n} decisions, the recording says choice_points={choice_points}"
        return None


# -- the state digest ----------------------------------------------------------------------

def _canon(x, out: list, _open: set | None = None) -> None:
    """Append a canonical byte encoding of ``x`` to ``out`` (floats bit for bit; dicts by
    sorted key encodings; other objects by their class and attributes, a cycle as a mark;
    functions by name; anything else by ``repr``)."""
    if _open is None:
        _open = set()
    if x is None or isinstance(x, (bool, np.bool_)):
        out.append(b"N" if x is None else (b"T" if x else b"F"))
    elif isinstance(x, (int, np.integer)):
        out.append(b"i%d;" % int(x))
    elif isinstance(x, (float, np.floating)):
        out.append(b"f" + struct.pack("<d", float(x)))
    elif isinstance(x, str):
        b = x.encode("utf-8", "surrogatepass")
        out.append(b"s%d:" % len(b) + b)
    elif isinstance(x, bytes):
        out.append(b"b%d:" % len(x) + x)
    elif isinstance(x, np.ndarray):
        a = np.ascontiguousarray(x)
        out.append(b"a" + str(a.dtype).encode() + repr(a.shape).encode() + a.tobytes())
    elif isinstance(x, (tuple, list)):
        out.append(b"(" if isinstance(x, tuple) else b"[")
        for y in x:
            _canon(y, out, _open)
        out.append(b")")
    elif isinstance(x, (dict, frozenset, set)) or hasattr(x, "items") and callable(x.items):
        items = []
        for k, v in (x.items() if hasattr(x, "items") else ((y, None) for y in x)):
            kb: list = []
            _canon(k, kb, _open)
            vb: list = []
            _canon(v, vb, _open)
            items.append((b"".join(kb), b"".join(vb)))
        out.append(b"{")
        for kb, vb in sorted(items):
            out.append(kb + b"=" + vb)
        out.append(b"}")
    elif hasattr(x, "__dataclass_fields__"):
        out.append(b"D" + type(x).__qualname__.encode())
        _canon(tuple(getattr(x, f) for f in x.__dataclass_fields__), out, _open)
    elif hasattr(x, "_fields"):        # namedtuple
        out.append(b"n" + type(x).__qualname__.encode())
        _canon(tuple(x), out, _open)
    elif isinstance(x, np.random.Generator):
        _canon(x.bit_generator.state, out, _open)
    elif isinstance(x, (type, types.FunctionType, types.BuiltinFunctionType, types.MethodType)):
        # a function by its name and what it closes over; a bound method with its object too
        out.append(b"c" + f"{getattr(x, '__module__', '')}.{getattr(x, '__qualname__', repr(x))}".encode())
        if isinstance(x, types.MethodType):
            _canon(x.__self__, out, _open)
        elif isinstance(x, types.FunctionType) and x.__closure__:
            _canon(tuple(c.cell_contents for c in x.__closure__), out, _open)
    elif hasattr(x, "__dict__") or hasattr(type(x), "__slots__"):
        if id(x) in _open:
            out.append(b"<cycle>")
            return
        _open.add(id(x))
        names = sorted(set(getattr(x, "__dict__", {})) | {n for c in type(x).__mro__
                                                          for n in getattr(c, "__slots__", ()) if hasattr(x, n)})
        out.append(b"o" + type(x).__qualname__.encode())
        _canon({n: getattr(x, n) for n in names if not n.startswith("__")}, out, _open)
        _open.discard(id(x))
    else:
        out.append(b"r" + repr(x).encode())


def canonical_bytes(x) -> bytes:
    """The canonical encoding :func:`state_digest` hashes (exposed for tests).

    >>> canonical_bytes({"b": 1, "a": 0.5}) == canonical_bytes({"a": 0.5, "b": 1})
    True
    >>> canonical_bytes(0.1 + 0.2) == canonical_bytes(0.3), canonical_bytes(0.0) == canonical_bytes(-0.0)
    (False, False)
    """
    out: list = []
    _canon(x, out)
    return b"".join(out)


def _mover_state(mover, n: int) -> tuple[list, dict]:
    """The motion model's changing state: per robot slot, its rows of the model's per-slot
    arrays (grid motion: cell, edge, progress, speed), and the model's other arrays and numbers."""
    per, common = [], {}
    for k, v in sorted(vars(mover).items()):
        if k.startswith("_"):
            continue
        if isinstance(v, np.ndarray) and v.ndim >= 1 and v.shape[0] == n:
            per.append(v)
        elif isinstance(v, (np.ndarray, int, float, bool)):
            common[k] = v
    return [tuple(a[k] for a in per) for k in range(n)], common


def _controller_fields(run, k: int) -> dict | None:
    """Every attribute of robot ``k``'s controller but the run's constants (its parameters, target
    and algorithm) and its generator (digested apart): ``state()`` need not return a controller's
    whole memory (wang2020's ``last_check``, handshake deadlines and queues are not in it), and
    whatever decides its future must be in the digest."""
    controllers = getattr(run, "controllers", None)
    c = controllers[k] if controllers is not None and k < len(controllers) else None
    if c is None:
        return None
    skip = {id(run.params), id(run.lattice), id(run.algorithm)}
    rng = run.robot_rngs[k] if k < len(getattr(run, "robot_rngs", ())) else None
    if rng is not None:
        skip.add(id(rng))
    names = set(getattr(c, "__dict__", {})) | {n for t in type(c).__mro__ for n in getattr(t, "__slots__", ())
                                               if hasattr(c, n)}
    return {n: getattr(c, n) for n in sorted(names) if id(getattr(c, n)) not in skip and not n.startswith("__")}


def _some_robot_drew(run) -> bool:
    """Whether some robot's generator is no longer at its seeded start (a robot drew)."""
    from .common import _robot_rng

    rngs = getattr(run, "robot_rngs", ()) or ()
    return any(g is not None and g.bit_generator.state != _robot_rng(run.seed, k).bit_generator.state
               for k, g in enumerate(rngs))


def state_digest(run, *, symmetric: bool = False) -> bytes:
    """A digest of everything that decides a run's future (issue 33): the step number, the
    poses bit for bit, who is present, each controller's ``state()`` and every attribute of it
    (:func:`_controller_fields`), each robot's generator,
    last step's broadcasts and what each robot heard, the messages in flight (queues, backlogs,
    exchanges), the clocks, the motion model's state, the fault generator, the quiet-step count
    and the choices still allowed (crashes left).

    With ``symmetric`` (anonymous robots: the model gives controllers no IDs) the robots are
    taken up to relabelling: a robot is named by its *key* (presence, pose, state, its motion
    state and clock, and its generator when the algorithm declares ``randomized = True``: a
    deterministic one's robots never draw, the contract oscillation's rule 1 relies on too),
    a message's sender by its sender's key, and the robots' rows are sorted, so two states that
    differ by a permutation of the robots have the same digest.  When two robots have the same
    key the permutation is not determined by the keys, and the digest falls back to slot order
    (it then merges fewer states, never more).

    Two states with the same digest are equal in every field listed (up to relabelling with
    ``symmetric``): a controller's memory counts whether its ``state()`` returns it or not (a
    value reached only through a closure, or a module-level global, is not seen).
    """
    n = run.n_total
    delivery, exchanges = run.delivery, run.exchanges
    moving, mover_common = _mover_state(run.mover, n)
    clocks = run.clocks
    clock = [(clocks.phase[k], clocks.rate[k]) if hasattr(clocks, "phase") else None for k in range(n)]
    # a deterministic algorithm's robots (no ``randomized = True``) never draw: up to relabelling
    # their generators (distinct per slot) are not part of who they are -- checked: a robot whose
    # generator moved makes them part of it again
    own_rng = not symmetric or getattr(run.algorithm, "randomized", False) or _some_robot_drew(run)
    keys = [canonical_bytes((bool(run.present[k]), run.poses[k].tobytes(), run.states[k] if run.states else None,
                             run.robot_rngs[k] if own_rng and k < len(run.robot_rngs) else None, moving[k],
                             clock[k], _controller_fields(run, k)))
            for k in range(n)]
    symmetric = symmetric and len(set(keys)) == n
    name = keys if symmetric else list(range(n))     # how a robot is referred to

    def pending_of(k):
        box = delivery.pending.get(k) or []
        # (due step, sender, message) in sending order: the global sequence numbers only say
        # the order, which the list keeps
        return [(e[0], name[e[2]], e[4]) for e in sorted(box, key=lambda e: (e[0], e[1]))]

    def listed(xs, k):
        return xs[k] if xs is not None and k < len(xs) else None

    rows = []
    for k in range(n):
        backlog = [(name[s], m) for s, m in delivery.backlog.get(k) or ()]
        rows.append(canonical_bytes((keys[k], listed(run.last_msgs, k), listed(run.heard_msgs, k),
                                     listed(run.outbox, k), listed(run.last_outbox, k), pending_of(k), backlog)))
    queue = [(e[0], e[2], name[e[3]], name[e[4]], e[5], e[6]) for e in sorted(exchanges.queue, key=lambda e: e[:2])]
    prev = sorted(keys[s] for s in run.idx_l_prev) if symmetric else list(run.idx_l_prev)
    common = canonical_bytes((int(run.t), int(run.quiet), run.fault_rng, sorted(queue) if symmetric else queue,
                              getattr(clocks, "every", None), mover_common, run.choices.crashes_left,
                              run.status, prev))
    h = hashlib.blake2b(digest_size=20)
    h.update(common)
    if symmetric:
        rows = sorted(rows)
        h.update(b"sym")
    else:
        h.update(canonical_bytes(list(run.ids_list)))
    for r in rows:
        h.update(struct.pack("<Q", len(r)))
        h.update(r)
    return h.digest()
