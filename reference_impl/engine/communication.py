"""Communication models: who hears whom, and how a delivery arrives (issue 12).

``RobotModel.communication``: ``"neighbors"`` (the robots in range, by the model's
neighbor rule), ``"all"`` (every robot: one shared read-only view per step, O(n) per
step) or ``"none"``.  Late deliveries (fault models: delay, duplication, reordering)
wait in the receiver's queue (:func:`_deliver_pending`); deliveries to a robot whose
asynchronous clock does not tick wait in its backlog (:meth:`Delivery.hold`).
"""

from __future__ import annotations

import heapq
from collections.abc import Mapping as _MappingABC

import numpy as np

from swarmproof.models.sensing import INCLUSIVE_SLACK
from swarmproof.models.trace import Event


class _AllBut(_MappingABC):
    """Read-only view of one step's broadcasts without the receiver's own (``communication="all"``):
    built once per step and shared, so delivery costs O(n) per step, not O(n^2)."""

    __slots__ = ("_base", "_own")

    def __init__(self, base: dict, own) -> None:
        self._base, self._own = base, own

    def __getitem__(self, key):
        if key == self._own:
            raise KeyError(key)
        return self._base[key]

    def __iter__(self):
        own = self._own
        return (k for k in self._base if k != own)

    def __len__(self) -> int:
        return len(self._base) - (self._own in self._base)

    def __contains__(self, key) -> bool:
        return key != self._own and key in self._base

    def __repr__(self) -> str:
        return repr(dict(self.items()))


def _deliver_pending(pending: dict, k: int, t: int, choices, to_id) -> tuple:
    """The deliveries due at step ``t`` for receiver slot ``k`` (robot ``to_id``; removed from
    ``pending``): ``((sender slot, message), ...)`` in delivery order.

    Due deliveries come in (due step, sending order), unless the run's choices reorder them
    (:meth:`.choices.Choices.order`: the fault model's ``message_reorder``, or a chooser).
    """
    box = pending.get(k)
    if not box:
        return ()
    due = [e for e in box if e[0] <= t]
    if not due:
        return ()
    pending[k] = [e for e in box if e[0] > t]
    due.sort(key=lambda e: (e[0], e[1]))
    if len(due) > 1:
        order = choices.order(t, to_id, len(due))
        if order is not None:
            due = [due[i] for i in order]
    return tuple((e[2], e[4]) for e in due)


class Delivery:
    """What each robot hears in a step: the model's audience, then the fault model's loss,
    delay, duplication and reordering (every draw from the fault generator, in delivery
    order), then anonymity (no sender IDs).

    Per run: ``Delivery(model, phi, ids_list, choices)`` (the run's
    :class:`.choices.Choices`: the draws, or a chooser's decisions); per step: :meth:`begin`
    (the broadcasts of the previous step), :meth:`receive` per deciding robot, :meth:`hold`
    per robot whose asynchronous clock did not tick (its backlog, read at its next tick),
    :meth:`end` (records ``drop`` and ``late_delivery`` events).
    """

    def __init__(self, model, phi: float, ids_list, choices) -> None:
        self.comm = model.communication
        self.anonymous = model.sensing == "anonymous"
        self.inclusive = getattr(model, "neighbor_rule", "strict") == "inclusive"
        self.phi, self.ids_list, self.choices = float(phi), ids_list, choices
        self.drops = choices.drops
        self.late = choices.late
        self.pending: dict = {}   # receiver slot -> [(due step, seq, sender slot, sender id, message)]
        #: receiver slot -> [(sender slot, message), ...] received in steps it did not decide (:meth:`hold`)
        self.backlog: dict = {}
        self.seq = 0
        #: local robots hearing their neighbors without message faults: the caller may build
        #: ``dict(zip(nb_ids, map(last_msgs.__getitem__, nb_slots)))`` itself when :attr:`direct`
        self.plain = (self.comm == "neighbors" and not self.anonymous and not self.drops and not self.late)
        self.direct = False

    def forget(self, slot: int) -> None:
        """A crashed robot loses its queue and its backlog (what it received but never read)."""
        self.pending.pop(slot, None)
        self.backlog.pop(slot, None)

    def begin(self, last_msgs: list, idx_l: list, silent: bool) -> None:
        """A step starts: ``last_msgs`` by slot (None: silent), the present slots, and whether
        some present robot was silent."""
        self.last_msgs = last_msgs
        ids_list = self.ids_list
        self.all_senders = [(ids_list[s], s) for s in idx_l] if self.comm == "all" else None
        self.all_msgs = ({sid: last_msgs[s] for sid, s in self.all_senders if last_msgs[s] is not None}
                         if self.comm == "all" and not (self.drops or self.late or self.anonymous) else None)
        self.silent = silent
        self.direct = self.plain and not self.silent
        self.dropped: list = []
        self.late_log: list = []

    def receive(self, t: int, k: int, my_id, nb_ids, nb_slots, nb_rel):
        """``(messages, delivered)`` for the robot in slot ``k``: its ``Observation.messages``
        and, when it differs from their items, the inbox (None otherwise).

        What :meth:`hold` kept for the robot (steps its clock did not tick) comes first, then
        this step's deliveries; ``messages`` keeps each sender's latest of them."""
        held = self.backlog.pop(k, None) if self.backlog else None
        if held is None:
            if self.all_msgs is not None:
                return _AllBut(self.all_msgs, my_id), None
            if self.direct:
                return dict(zip(nb_ids, map(self.last_msgs.__getitem__, nb_slots))), None
        got = self._incoming(t, k, my_id, nb_ids, nb_slots, nb_rel)
        if held is not None:
            got = held + got
        return self._as_observed(got, nb_slots, self.late or held is not None)

    def hold(self, t: int, k: int, my_id, nb_ids, nb_slots, nb_rel) -> None:
        """The robot in slot ``k`` does not decide in step ``t`` (its clock did not tick): what
        it would have received now waits for its next tick (:meth:`receive`), oldest first.

        The deliveries are made exactly as for a deciding robot (the same audience, and the same
        loss, delay and duplication draws, in slot order), so a slow clock neither loses nor
        adds a message (docs/decisions.md, "Engine: asynchronous clocks (issue 15)")."""
        got = self._incoming(t, k, my_id, nb_ids, nb_slots, nb_rel)
        if got:
            self.backlog.setdefault(k, []).extend(got)

    def _incoming(self, t: int, k: int, my_id, nb_ids, nb_slots, nb_rel) -> list:
        """This step's deliveries to slot ``k``: ``[(sender slot, message), ...]`` in delivery
        order (the model's audience, then the fault model's loss, delay, duplication and
        reordering, every draw from the fault generator)."""
        last_msgs, choices = self.last_msgs, self.choices
        late = self.late
        if self.comm == "none":
            heard = ()
        elif self.comm == "all":
            heard = [(sid, s) for sid, s in self.all_senders if s != k]
        elif self.anonymous:
            # anonymous robots sense everyone; they hear the ones in range
            d = np.hypot(nb_rel[:, 0], nb_rel[:, 1])
            near = (d <= self.phi * INCLUSIVE_SLACK) if self.inclusive else (d < self.phi)
            heard = [(self.ids_list[s], s) for s, ok in zip(nb_slots, near.tolist()) if ok]
        else:
            heard = zip(nb_ids, nb_slots)
        if not self.drops and not late:
            return [(s, last_msgs[s]) for _, s in heard if last_msgs[s] is not None]
        got = []
        for sid, s in heard:
            msg = last_msgs[s]
            if msg is None:
                continue
            if choices.lost(t, sid, my_id):
                self.dropped.append((sid, my_id))
                continue
            if late:
                delay = choices.delay(t, sid, my_id)
                copies = choices.copies(t, sid, my_id)
                box = self.pending.setdefault(k, [])
                for _ in range(copies):
                    box.append((t + delay, self.seq, s, sid, msg))
                    self.seq += 1
                if delay or copies > 1:
                    self.late_log.append((sid, my_id, t + delay, copies))
            else:
                got.append((s, msg))
        if late:
            return list(_deliver_pending(self.pending, k, t, choices, my_id))
        return got

    def _as_observed(self, got: list, nb_slots, inbox: bool):
        """``(messages, delivered)`` of deliveries ``[(sender slot, message)]``: ``messages``
        keyed by sender ID (anonymous: by the row of ``neighbor_poses`` the sender is sensed at;
        messages of robots not sensed now are in the inbox only), each sender's latest;
        ``delivered`` the inbox when ``inbox`` (or anonymous), else None."""
        if self.anonymous:
            row = {s: r for r, s in enumerate(nb_slots)}
            return ({row[s]: m for s, m in got if s in row}, tuple((None, m) for _, m in got))
        ids_list = self.ids_list
        msgs = {ids_list[s]: m for s, m in got}
        return msgs, (tuple((ids_list[s], m) for s, m in got) if inbox else None)

    def end(self, t: int, events: list) -> None:
        if self.dropped:
            events.append(Event(t, "drop", (), (("deliveries", tuple(self.dropped)),)))
        if self.late_log:
            events.append(Event(t, "late_delivery", (), (("deliveries", tuple(self.late_log)),)))


class Exchanges:
    """Point-to-point exchanges (``Controller.requests``): a request and its answer within the step.

    A request goes to a robot the sender can hear from now (the model's audience); the fault
    model's loss (``drop_message``, ``message_loss``) and delay (``message_delay``) apply to
    each direction, drawn from the fault generator in sending order; duplication and
    reordering are the broadcasts' only.  Without faults a request is answered, and the answer
    is read, in the step it was sent: the model of a link whose latency is negligible (004 Sec.
    II-A e).  A robot that is gone when a request or answer is due loses it.

    Per run one object; per step :meth:`send` for every robot that asked, then :meth:`due`
    hands the deliveries due now to the engine's exchange phase, oldest first, and :meth:`end`
    records the lost and late ones (``drop`` and ``late_delivery`` events, key ``exchanges``).
    """

    def __init__(self, model, ids_list, choices) -> None:
        self.comm = model.communication
        self.anonymous = model.sensing == "anonymous"
        self.choices = choices
        self.ids_list = ids_list
        self.slot_of = {int(r): s for s, r in enumerate(ids_list)}
        self.queue: list = []       # heap of (due step, seq, kind, from slot, to slot, payload, reply)
        self.seq = 0
        self.dropped: list = []
        self.late_log: list = []

    def _fate(self, t: int, from_id: int, to_id: int):
        """None (lost) or the step a delivery from ``from_id`` to ``to_id`` sent at ``t`` arrives."""
        if self.choices.lost(t, from_id, to_id):
            self.dropped.append((from_id, to_id))
            return None
        d = self.choices.delay(t, from_id, to_id)
        if d:
            self.late_log.append((from_id, to_id, t + d, 1))
        return t + d

    def _push(self, due: int, kind: str, a: int, b: int, payload, reply=None) -> None:
        heapq.heappush(self.queue, (due, self.seq, kind, a, b, payload, reply))
        self.seq += 1

    def send(self, t: int, k: int, my_id, requests, audience) -> None:
        """The requests of the robot in slot ``k`` (``Controller.requests``) to the robots it can
        hear from now (``audience``: their IDs; None: every present robot)."""
        from swarmproof.models.errors import ProtocolError

        if self.anonymous or my_id is None:
            raise ProtocolError(f"a robot without an ID returned requests()={requests!r} at step {t}: "
                                "an exchange needs the robots' IDs (RobotModel.sensing != 'anonymous')")
        try:
            pairs = [(int(peer), payload) for peer, payload in requests]
        except (TypeError, ValueError):
            raise ProtocolError(f"controller of robot {my_id!r} returned requests()={requests!r} at step "
                                f"{t}; expected ((peer_id, payload), ...)") from None
        heard = None if audience is None else set(int(i) for i in audience)
        for peer, payload in pairs:
            s = self.slot_of.get(peer)
            if s is None or self.comm == "none" or (heard is not None and peer not in heard) or peer == int(my_id):
                self.dropped.append((int(my_id), peer))
                continue
            due = self._fate(t, int(my_id), peer)
            if due is not None:
                self._push(due, "request", k, s, payload)

    def answered(self, t: int, a: int, b: int, a_id: int, b_id: int, payload, reply) -> None:
        """The robot in slot ``b`` answered ``reply`` to slot ``a``'s request: send it back."""
        due = self._fate(t, b_id, a_id)
        if due is not None:
            self._push(due, "reply", a, b, payload, reply)

    def due(self, t: int):
        """The next delivery due at or before step ``t`` (removed), or None."""
        if self.queue and self.queue[0][0] <= t:
            return heapq.heappop(self.queue)
        return None

    def forget(self, slot: int) -> None:
        """A crashed robot: what it would still receive is lost (a ``drop``)."""
        ids = self.ids_list
        keep = []
        for e in self.queue:
            to, frm = (e[4], e[3]) if e[2] == "request" else (e[3], e[4])
            if to == slot:
                self.dropped.append((ids[frm], ids[to]))
            else:
                keep.append(e)
        self.queue = keep
        heapq.heapify(self.queue)

    def end(self, t: int, events: list) -> None:
        if self.dropped:
            events.append(Event(t, "drop", (), (("exchanges", tuple(self.dropped)),)))
            self.dropped = []
        if self.late_log:
            events.append(Event(t, "late_delivery", (), (("exchanges", tuple(self.late_log)),)))
            self.late_log = []
