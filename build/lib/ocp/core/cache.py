"""The suite's caches of built objects (CasADi NLPs and functions), all cleared by one call.

A cold timing clears them first (`clear()`); the compiled Taylor kernels of `ocp.indirect.taylor`
are numba's on-disk compilations, not state of a run."""

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
