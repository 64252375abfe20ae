"""Who is told of every finished exploration (``listener(report)``).

A module of its own that imports nothing, so the pytest plugin can listen without loading
the explorer in test sessions that never explore.
"""

#: Callables called with each :class:`~swarmproof.checkers.explore.ExploreReport` when
#: :func:`~swarmproof.checkers.explore.explore` returns it.
REPORT_LISTENERS: list = []
