"""The contract of a direct transcription, in the spirit of scipy's `OdeSolver`.

Every transcription has free final time: time is scaled to s = t/T in [0, 1], cut into N equal
intervals with a constant control u_k in CONTROL_BOUNDS each; the node states
z_k = (theta_k, omega_k, T_k) carry T as a state (constant across the stages), so the NLP is
stagewise, as structure-exploiting solvers (fatrop) require. A transcription is a frozen
dataclass (plain data: it travels to worker processes) and implements:

    1. `name`: its key in `ocp.direct.TRANSCRIPTIONS`
    2. its settings as dataclass fields, each declared in `SETTINGS` (a `Setting`: type, range,
       help; the command line's flags are made from them) and checked by `check_settings()` in
       `__post_init__` (InputError)
    3. `applicable()`: the names of the settings that apply (an option given that does not apply is
       an error, not ignored: `ocp.direct.make`)
    4. `extra`: NLP variables per stage besides z_k and u_k (e.g. collocation states)
    5. `prepare()`: what every stage shares, built once per NLP (an integrator's map, a matrix)
    6. `stage(x, u, h, kappa, extra, prepared)`: the state at the end of the interval and the
       stage's own constraints (expressions that must vanish), in CasADi symbols
    7. `describe()`: one line for summaries; `family()`: the short label of charts without N
"""

from dataclasses import asdict, dataclass, fields

from ..core.errors import InputError, finite, integer

N_MAX = 5000     # the NLP of N = 5000 (rk4, M = 4) takes about 1 GB to build; larger is refused


@dataclass(frozen=True)
class Setting:
    """One setting of a transcription: its type (int, float or str), default, range or choices, and
    a one-line help. The command line's `--NAME` flags, their help and their checks are made from
    these (`ocp.direct.settings()`)."""

    name: str
    kind: type
    default: object
    help: str
    low: float | None = None
    high: float | None = None
    choices: tuple = ()

    def accepted(self):
        """What the setting accepts, in words."""
        if self.choices:
            return f"one of {', '.join(map(str, self.choices))}"
        what = {int: "an integer", float: "a number"}[self.kind]
        return f"{what} from {self.low:g} to {self.high:g}"

    def parse(self, value):
        """`value` (text or a number) as the setting's type, checked; InputError names the setting
        and what it accepts."""
        accepted = f"{self.accepted()} ({self.help})"
        if self.choices:
            if value not in self.choices:
                raise InputError(f"{self.name} = {str(value)[:40]!r} is not accepted; {self.name} accepts {accepted}")
            return value
        if self.kind is int:
            return integer(self.name, value, accepted, self.low, self.high)
        return finite(self.name, value, accepted, self.low, self.high)


class Transcription:
    name = ""
    extra = 0
    symbolic = "SX"          # "MX" where an integrator call cannot be expanded (cvodes)
    #: every setting the transcription can take (the dataclass fields), with type, range and help
    SETTINGS = ()

    def check_settings(self):
        """Each setting's value checked by its declaration (InputError)."""
        for setting in self.SETTINGS:
            setting.parse(getattr(self, setting.name))

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
