import math
from swarmproof.reference_impl.protocol import Command, RobotModel, connected_start, steer_toward


class _Base:
    model = RobotModel()
    assumptions = (connected_start(),)

    def finished(self, states):
        return False


class _C:
    def __init__(self, rid, params):
        self.rid, self.params, self.k = rid, params, 0

    def state(self):
        return (("k", self.k),)


class Crashy(_Base):
    name = "crashy"

    def controller(self, rid, params, target, rng):
        class C(_C):
            def step(self, obs):
                self.k += 1
                if len(obs.neighbor_ids) >= 2 and self.k > 3:
                    return Command(forward=1 / (len(obs.neighbor_ids) - len(obs.neighbor_ids)))
                return Command(turn=0.1, forward=0.01)
        return C(rid, params)


class TupleCmd(_Base):
    name = "tuple-cmd"

    def controller(self, rid, params, target, rng):
        class C(_C):
            def step(self, obs):
                return (0.0, 0.1)
        return C(rid, params)


class NaNTurn(_Base):
    name = "nan-turn"

    def controller(self, rid, params, target, rng):
        class C(_C):
            def step(self, obs):
                return Command(turn=math.nan)
        return C(rid, params)


class DictState(_Base):
    name = "dict-state"

    def controller(self, rid, params, target, rng):
        class C(_C):
            def step(self, obs):
                return Command()

            def state(self):
                return {"k": 1}
        return C(rid, params)


class NeedsArg(_Base):
    name = "needs-arg"

    def __init__(self, speed):
        self.speed = speed

    def controller(self, rid, params, target, rng):
        return None


class CentroidGather(_Base):
    """Every robot steers to the centroid of what it senses; no spanning tree, no 'parent'."""

    name = "centroid-gather"

    def controller(self, rid, params, target, rng):
        class C(_C):
            def step(self, obs):
                self.k += 1
                if len(obs.neighbor_poses) == 0:
                    return Command()
                x, y = obs.neighbor_poses[:, :2].mean(axis=0)
                return steer_toward((float(x) / 2, float(y) / 2), self.params)
        return C(rid, params)
