"""The contract of a direct transcription, in the spirit of scipy's `OdeSolver`.

Every transcription has free final time: time is scaled to s = t/T in [0, 1], cut into N equal
intervals with a constant control u_k in CONTROL_BOUNDS each; the node states
z_k = (theta_k, omega_k, T_k) carry T as a state (constant across the stages), so the NLP is
stagewise, as structure-exploiting solvers (fatrop) require. A transcription is a frozen
dataclass (plain data: it travels to worker processes) and implements:

    1. `name`: its key in `ocp.direct.TRANSCRIPTIONS`
    2. its settings as dataclass fields, checked in `__post_init__` (InputError)
    3. `applicable()`: the names of the settings that apply (an option given that does not apply is
       an error, not ignored: `ocp.direct.make`)
    4. `extra`: NLP variables per stage besides z_k and u_k (e.g. collocation states)
    5. `prepare()`: what every stage shares, built once per NLP (an integrator's map, a matrix)
    6. `stage(x, u, h, kappa, extra, prepared)`: the state at the end of the interval and the
       stage's own constraints (expressions that must vanish), in CasADi symbols
    7. `describe()`: one line for summaries; `family()`: the short label of charts without N
"""

from dataclasses import asdict, fields

from ..core.errors import InputError, integer

N_MAX = 5000     # the NLP of N = 5000 (rk4, M = 4) takes about 1 GB to build; larger is refused


class Transcription:
    name = ""
    extra = 0
    symbolic = "SX"          # "MX" where an integrator call cannot be expanded (cvodes)

    def check_N(self):
        integer("N", self.N, f"an integer from 2 to {N_MAX} (intervals)", 2, N_MAX)

    def applicable(self):
        return tuple(f.name for f in fields(self))

    def prepare(self):
        return None

    def stage(self, x, u, h, kappa, extra, prepared):
        raise NotImplementedError

    def describe(self):
        raise NotImplementedError

    def family(self):
        raise NotImplementedError

    def to_dict(self):
        return dict({k: v for k, v in asdict(self).items() if k in self.applicable()}, transcription=self.name)


def settings_error(transcription, given):
    """InputError for the settings in `given` that do not apply to `transcription`."""
    extra = sorted(set(given) - set(transcription.applicable()))
    if extra:
        raise InputError(f"{', '.join(extra)} do{'es' if len(extra) == 1 else ''} not apply to {transcription.describe()}; "
                         f"it takes: {', '.join(transcription.applicable())}")
