"""Song & O'Kane 2014: decentralized formation of arbitrary multi-robot lattices.

Song & O'Kane, "Decentralized Formation of Arbitrary Multi-Robot Lattices", ICRA 2014
(seed 000_3ad33c5b62f11d5f.txt; docs/references.md, docs/song2014.md).

The package holds everything about this paper:

* :mod:`.algorithm` -- the reference implementation (authority trees, local Hungarian
  matching, bounded-range motion of Lemma 7, dispersal of unmatched robots);
  registered as ``song2014``;
* :mod:`.monitors` -- the runtime monitor of Lemma 7's premise as this paper states it;
* :mod:`.experiments` -- Sec. V's runs as functions (formation, robustness, execution time).

The lemmas (Lemma 7, bounded range) are shared with Song & O'Kane 2016 and live in
:mod:`swarmproof.reference_impl.song2016.lemmas`.
"""

from . import monitors as _monitors  # noqa: F401  (registers this paper's premise monitor)
from .algorithm import *  # noqa: F401,F403
from .algorithm import __all__  # noqa: F401
