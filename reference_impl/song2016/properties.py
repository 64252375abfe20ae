"""Song & O'Kane 2016's own property: every tree link in a case of Lemma 11's argument (issue 19).

``tree_link_cases`` checks, for every link of the spanning tree a step decided, which case of
the paper's argument for Lemma 11 covers it, by the algorithm's own reasons (the child among the
children its parent decided the step with, the parent inside the child's bounded range; the
parent still and the child not farther; the relocate robot under the root), and lists every link
no case covers.  It was a premise monitor until issue 32; it is a property because no lemma
states it: ``spanning_tree_kept`` proves that a link *in* a case is kept, and each of its
geometric cases is monitored from that definition (``nclb``: the premises of ``nclb_link_kept``,
the NCLB case; ``child_toward_parent``: the case ``child_not_farther_from_still_parent``), while
which case the algorithm's decision puts a link in -- and the relocate robot's link to the
root, a case no lemma covers -- is what this property adds (docs/proofs.md, "Premise monitors").

Importing this module registers it (:func:`~swarmproof.invariants.registry.register_property`,
``own=True``): song2016 and its variants list it in ``properties``; ``explore``, ``verify`` and
``simulate`` judge it for them, streamed in the engine on every step.

References
----------
001_7a4e517b856331bc.txt Lemma 11's proof, Sec. V-C (NCLB, relocate robot), Def. 8.
"""

from __future__ import annotations

from swarmproof.invariants.premises import StepFeed
from swarmproof.invariants.registry import Property, register_property

from .monitors import TreeLinkCases, tree_links_in_proved_cases

__all__ = ["TREE_LINK_CASES_PROPERTY"]

_CITES = "001 Lemma 11's proof, Sec. V-C, Def. 8 (the cases of spanning_tree_kept; the relocate robot under the root)"


def _check(trace, ctx):
    return tree_links_in_proved_cases(trace, ctx.phi, float(ctx.params.v), float(ctx.params.dt))


def _stream(algorithm, params, options):
    return StepFeed("tree_link_cases", TreeLinkCases(float(params.range), float(params.v), float(params.dt)))


#: ``tree_link_cases``: every link of the tree a step decided is in a case of Lemma 11's argument,
#: by the algorithm's own reasons; violated with every uncovered link listed
#: (``detail["uncovered_links"]``), the witness the first that broke, else the first.
TREE_LINK_CASES_PROPERTY = register_property(Property(
    "tree_link_cases", "safety", _check,
    ("poses", "states' parent, children, relocate, root_id", "range, v, dt"),
    "step ends only (straight motion assumed in between); links between robots that were not neighbours at the "
    "step's start are not examined (tree_links counts them); a link no case covers is a finding whether or not it "
    "broke; the relocate robot's link to the root is checked directly (no lemma covers that case)",
    _CITES, stream=_stream, every_step=True, needs=("parent", "range_graph"), own=True))
