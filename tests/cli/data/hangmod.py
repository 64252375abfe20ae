"""Algorithms whose own code does not return (issue 29 item 9): the budget must hold against them."""

from swarmproof.reference_impl.protocol import Command, RobotModel, connected_start


class _Base:
    model = RobotModel()
    assumptions = (connected_start(),)

    def finished(self, states):
        return False


class _Controller:
    def __init__(self, hang_at: int) -> None:
        self.k, self.hang_at = 0, hang_at

    def step(self, obs):
        self.k += 1
        while self.k > self.hang_at:       # never returns; and swallows what an Exception can say
            try:
                self.k += 1
            except Exception:  # noqa: BLE001 - on purpose: the watchdog is not an Exception
                pass
        return Command(turn=0.1, forward=0.01)

    def state(self):
        return (("k", min(self.k, 3)),)


class Hangs(_Base):
    """Every robot's step hangs at its third call."""

    name = "hangs"

    def controller(self, robot_id, params, target, rng):
        return _Controller(hang_at=2)
