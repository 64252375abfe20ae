"""The deterministic simulation engine (see :mod:`.run` for the model and the step).

The run loop is :func:`~.run.simulate`, a short driver over the phase functions of
:mod:`.phases`; the phases use the models of the sibling modules: :mod:`.faults`
(schedules, crashes, additions, message and sensing faults), :mod:`.sensing` (what a robot
perceives), :mod:`.communication` (who hears whom, late deliveries), :mod:`.motion`
(differential, holonomic, grid) and :mod:`.clocks` (synchronous or asynchronous).
"""

from .faults import DropSet, FaultModel, TableSchedule
from .run import (ENGINE_ASSUMPTIONS, PROGRESS_EVERY, SimulationResult, Trace, default_max_steps,
                  default_static_window, simulate)

__all__ = [
    "simulate", "SimulationResult", "Trace", "FaultModel", "TableSchedule", "DropSet", "default_max_steps",
    "default_static_window", "ENGINE_ASSUMPTIONS", "PROGRESS_EVERY",
]
