"""Cold timings are cold: every memoised builder of the suite is registered with `ocp.core.cache`, so
that `clear()` (called by the bench before each repeat) forgets every CasADi object it built."""

import importlib
from pathlib import Path

import ocp
from ocp.core import cache


def _memoised():
    """Every functools-memoised function defined in an ocp module: (module.name, function). Modules
    are found by file (ocp/core is a namespace package, which pkgutil does not list)."""
    root = Path(ocp.__file__).parent
    found = []
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        module = importlib.import_module(name)
        for attr, value in vars(module).items():
            if hasattr(value, "cache_info") and getattr(value, "__module__", None) == name:
                found.append((f"{name}.{attr}", value))
    return found


def test_every_memoised_builder_is_registered():
    found = _memoised()
    assert len(found) >= 5                                   # nlp build, costate, certificate flow, falling flow, ...
    unregistered = [name for name, f in found if f not in cache._CACHES]
    assert not unregistered, f"memoised outside ocp.core.cache (a cold timing would reuse them): {unregistered}"


def test_clear_forgets_every_built_object():
    from ocp import direct
    from ocp.scenes import falling

    ocp.solve(ocp.swing_up(1.0), ocp.MultipleShooting(N=20))        # NLP, costate function, certificate flow
    falling.fall_time_casadi((3.0, 0.0), "cvodes")                     # a CasADi integrator
    direct.nlp.build(ocp.MultipleShooting(N=20))
    assert sum(memo.cache_info().currsize for memo in cache._CACHES) >= 4
    cache.clear()
    assert all(memo.cache_info().currsize == 0 for memo in cache._CACHES)
