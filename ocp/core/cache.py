"""The suite's caches of built objects (CasADi NLPs, integrators and functions, and the constants
of Finch's formulas), all cleared by one call.

A cold timing clears them first (`clear()`): every CasADi object the suite builds is then built
again (tests/test_cache.py fails on a memoised builder that is not registered here). What a cold
timing in a running process still reuses, because no call can undo it: the shared libraries of
the CasADi plugins (IPOPT, fatrop, ...) once loaded. (The compiled kernels of the search and the
synthesis are C extensions, built by the install: nothing is compiled at run time.)"""

import functools

_CACHES = []


def cached(function):
    """`function` memoised on its (hashable) arguments, its cache registered for `clear`."""
    memo = functools.lru_cache(maxsize=64)(function)
    _CACHES.append(memo)
    return memo


def clear():
    """Forget every built object: the next use builds it again, cold."""
    for memo in _CACHES:
        memo.cache_clear()
