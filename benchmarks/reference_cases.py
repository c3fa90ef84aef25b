"""The four reference cases of Finch (2015) from the standard starts, with their exact transfers:
name -> (problem, function returning the `ocp.exact.finch.BangBang`: one or two switches)."""

import ocp
from ocp.exact import finch

CASES = {
    "swing-up kappa=1": (ocp.swing_up(1.0), lambda: finch.one_switch("swing-up", 1.0)),
    "damping kappa=1": (ocp.damping(1.0), lambda: finch.one_switch("damping", 1.0)),
    "swing-up kappa=1/2": (ocp.swing_up(0.5), lambda: finch.two_switch("swing-up", 0.5)),
    "swing-up kappa=3/4": (ocp.swing_up(0.75), lambda: finch.two_switch("swing-up", 0.75)),
}
