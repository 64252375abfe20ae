"""Who is told of every finished exploration (``listener(report)``).

A module of its own that imports nothing, so a listener (the pytest plugin's property
table) can register without loading the explorer in sessions that never explore.
:mod:`swarmproof.listeners` re-exports the same list for code that imports it there.

Examples
--------
>>> seen = []
>>> REPORT_LISTENERS.append(seen.append)
>>> REPORT_LISTENERS.remove(seen.append)
"""

#: Callables called with each :class:`~swarmproof.checkers.explore.ExploreReport` when
#: :func:`~swarmproof.checkers.explore.explore` returns it.
REPORT_LISTENERS: list = []
