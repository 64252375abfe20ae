"""Small example algorithms of other kinds than the papers' (docs/engine.md).

:mod:`.algorithms` holds ``example-gather`` (robots gather behind the lowest ID),
``example-anonymous-line`` (anonymous robots forming a line) and ``example-grid-goals``
(grid robots with asynchronous clocks); they show how a user's own algorithm plugs in.
:mod:`.lemmas` holds example-gather's lemma and the binding of its runtime monitor
(docs/lemmas.md).
"""

from . import lemmas as _lemmas  # noqa: F401  (registers example-gather's monitor, gather_link)
from .algorithms import *  # noqa: F401,F403
from .algorithms import __all__  # noqa: F401
