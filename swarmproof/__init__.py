"""swarmproof: machine-checked properties of decentralized multi-robot formation algorithms.

The public facade (DESIGN.md section 1).  Import from here or from the
subpackages ``swarmproof.models``, ``swarmproof.reference_impl``,
``swarmproof.invariants`` and ``swarmproof.checkers``.
"""

__version__ = "0.1.0"

#: The facade's names, imported on first use (PEP 562): ``import swarmproof`` stays light, so the
#: console script handles Ctrl-C before numpy and the rest load (swarmproof.entry).
_LAZY = {"SE2": "swarmproof.models", "AssumptionError": "swarmproof.models", "Edge": "swarmproof.models",
         "InputFileError": "swarmproof.models", "LatticeGraph": "swarmproof.models",
         "SwarmproofError": "swarmproof.models", "UsageError": "swarmproof.models",
         "Verdict": "swarmproof.models.verdict"}


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'swarmproof' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value

__all__ = [
    "__version__", "SE2", "Edge", "LatticeGraph", "Verdict",
    "SwarmproofError", "UsageError", "InputFileError", "AssumptionError", "replay_file",
]


def replay_file(path):
    """Re-run a counterexample file (``swarmproof replay FILE``) and return the
    :class:`~swarmproof.checkers.replay.ReplayResult`: ``.reproduced`` is True while the
    violation still happens.  A kept counterexample is a regression test::

        def test_the_split_stays_fixed():
            assert not swarmproof.replay_file("cx/mine-connectivity-seed0.json").reproduced
    """
    from swarmproof.checkers.replay import replay_file as _replay_file

    return _replay_file(path)
