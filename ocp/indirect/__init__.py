"""The indirect side: Pontryagin extremals of the minimum-time problem.

`taylor` integrates the state-costate system (compiled: C), `search` scans the whole
one-parameter family of extremals from a start for every arrival at the target set, and
`certificate` checks an extremal by independent means (first- and second-order conditions).
"""

from .certificate import Certificate, certify
from .searching import Coverage, Extremal, Search, search

__all__ = ["Certificate", "certify", "Coverage", "Extremal", "Search", "search"]
