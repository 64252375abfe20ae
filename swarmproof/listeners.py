"""Who is told of every finished exploration (``listener(report)``).

The list lives in :mod:`swarmproof.checkers.listeners` (the explorer, a lower layer,
calls it); this is the same list under its public name.  Neither module imports
anything else, so the pytest plugin can listen without loading the explorer in test
sessions that never explore.
"""

from swarmproof.checkers.listeners import REPORT_LISTENERS

__all__ = ["REPORT_LISTENERS"]
