"""Song & O'Kane 2016: forming repeating patterns of mobile robots, provably.

Song & O'Kane, "Forming repeating patterns of mobile robots: a provably correct decentralized
algorithm", IROS 2016 (seed 001_7a4e517b856331bc.txt; docs/references.md, docs/song2016.md).

The package holds everything about this paper:

* :mod:`.algorithm` -- the reference implementation of Sec. V and Algorithm 1 (registered as
  ``song2016``, the literal Sec. V-B parent rule as ``song2016-literal``, and the relocate
  robot's movement timeout counted from its line-29 subtree marker as ``song2016-subtree-clock``);
* :mod:`.geometry` -- the motion geometry: bounded ranges (Def. 8), safe regions, NCLB;
* :mod:`.lemmas` -- the z3 encodings of the geometric safety lemmas (Lemma 7, NCLB,
  Lemma 11's per-link cases; also those of 000 Lemma 7) and the whole-tree cases of Lemma 11;
* :mod:`.monitors` -- the runtime monitors of those lemmas' premises;
* :mod:`.properties` -- its own property ``tree_link_cases`` (every tree link in a case of
  Lemma 11's argument), which no lemma states.
"""

from . import monitors as _monitors  # noqa: F401  (registers this paper's premise monitors)
from . import properties as _properties  # noqa: F401  (registers this paper's own properties)
from .algorithm import *  # noqa: F401,F403
from .algorithm import __all__  # noqa: F401
