"""The direct side: transcriptions of the minimum-time problem into NLPs, their solve and the
switching structure read off the answer.

TRANSCRIPTIONS is the registry used by the command line, the benchmark and the summaries; a new
transcription is one module (a subclass of `ocp.direct.base.Transcription`) and one line here.
"""

from ..core.errors import InputError
from .base import settings_error
from .collocation import DirectCollocation
from .guess import Guess, default_guesses, random_guess
from .shooting import INTEGRATORS, MultipleShooting
from .solve import MESSAGES, MISS_TOL, MISS_TOL_RANGE, DirectSolution, DirectStatus, solve

TRANSCRIPTIONS = {
    "multiple-shooting": MultipleShooting,
    "direct-collocation": DirectCollocation,
}


def settings():
    """Every transcription setting by name, as declared (`Setting`): the command line's flags.
    A name that several transcriptions take (N) is declared alike in each."""
    declared = {}
    for cls in TRANSCRIPTIONS.values():
        for setting in cls.SETTINGS:
            if declared.setdefault(setting.name, setting) != setting:
                raise AssertionError(f"setting {setting.name} is declared differently by two transcriptions")
    return declared


def make(name, **settings):
    """The transcription `name` with `settings` (only those given; each must apply to it)."""
    if name not in TRANSCRIPTIONS:
        raise InputError(f"unknown transcription {name!r}; accepted: {', '.join(TRANSCRIPTIONS)}")
    cls = TRANSCRIPTIONS[name]
    known = {s.name for c in TRANSCRIPTIONS.values() for s in c.SETTINGS}
    unknown = sorted(set(settings) - known)
    if unknown:
        raise InputError(f"unknown transcription setting(s) {', '.join(unknown)}; accepted: {', '.join(sorted(known))}")
    foreign = {k: v for k, v in settings.items() if k not in cls.__dataclass_fields__}
    if foreign:
        settings_error(cls(), foreign)
    transcription = cls(**settings)
    settings_error(transcription, settings)
    return transcription


__all__ = ["TRANSCRIPTIONS", "settings", "INTEGRATORS", "MultipleShooting", "DirectCollocation", "Guess", "default_guesses",
           "random_guess", "solve", "make", "DirectSolution", "DirectStatus", "MESSAGES", "MISS_TOL", "MISS_TOL_RANGE"]
