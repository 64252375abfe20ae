"""Citations people can read without the seed files (docs/references.md).

Code and JSON cite a paper by its seed key (``001 Lemma 11``, or the seed file's name);
what a person reads says ``Song & O'Kane 2016, Lemma 11``.  :func:`readable` turns the one
into the other; the command line passes every human line and every error through it.

>>> readable("001 Lemma 11 (connectivity is preserved)")
"Song & O'Kane 2016, Lemma 11 (connectivity is preserved)"
>>> readable("bounded_range (000/001 Lemma 7)")
"bounded_range (Song & O'Kane 2014/2016, Lemma 7)"
>>> readable("000_3ad33c5b62f11d5f.txt Lemma 7, Eqs. 5-7; 001_7a4e517b856331bc.txt Lemma 7")
"Song & O'Kane 2014, Lemma 7, Eqs. 5-7; Song & O'Kane 2016, Lemma 7"
>>> readable("issue 6 / 001 Def. 5, Thm. 13: no static configuration short of the goal")
"Song & O'Kane 2016, Def. 5, Thm. 13: no static configuration short of the goal"
>>> readable("see DESIGN.md section 5")
'see docs/README.md'
>>> readable("step 001 of 1.000 Lemma")   # not a citation: left alone
'step 001 of 1.000 Lemma'
"""

from __future__ import annotations

import re

__all__ = ["PAPERS", "readable"]

#: Seed key -> the short name people read (docs/references.md).
PAPERS = {"000": "Song & O'Kane 2014", "001": "Song & O'Kane 2016", "002": "Jiang et al.",
          "003": "Lee & Chong 2008", "004": "Wang & Rubenstein 2020"}

_SEED_FILE = re.compile(r"\b(00[0-4])_[0-9a-f]{16}\.txt\b")
_PAIR = re.compile(r"(?<![\w.])(000)/(001)(?= [A-Z(])")
_ONE = re.compile(r"(?<![\w./])(00[0-4])(?= (?:Sec\.|Def|Lemma|Thm|Theorem|Eq|Fig|Table|Algorithm|Alg\.|Cor|Prop)"
                  r"| ?[,;)]|$)")
_ISSUE = re.compile(r"\bissues? \d+(?: / | \(|: )")
_DESIGN = re.compile(r"\(?DESIGN\.md(?: section \d+)?\)?")


def readable(text: str) -> str:
    """``text`` with every seed-key citation written as the paper's short name."""
    if not text or not any(c.isdigit() for c in text) and "DESIGN" not in text:
        return text
    text = _SEED_FILE.sub(lambda m: m.group(1), text)
    text = _PAIR.sub("Song & O'Kane 2014/2016,", text)
    text = _ONE.sub(lambda m: PAPERS[m.group(1)] + ",", text)
    text = text.replace(",,", ",").replace(", ,", ",").replace(",;", ";").replace(",)", ")")
    text = _ISSUE.sub(lambda m: "" if m.group(0).endswith(" / ") else m.group(0), text)
    text = _DESIGN.sub(lambda m: "(docs/README.md)" if m.group(0).startswith("(") else "docs/README.md", text)
    return text
