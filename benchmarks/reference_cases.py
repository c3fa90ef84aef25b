"""The four reference cases of the swing-up paper (issue 2) with their exact solutions:
name -> (problem, function returning the analytic BangBang of ocp.analytic)."""

import ocp
from ocp import analytic

CASES = {
    "swing-up kappa=1": (ocp.swing_up(1.0), lambda: analytic.one_switch("swing-up", 1.0)),
    "damping kappa=1": (ocp.damping(1.0), lambda: analytic.one_switch("damping", 1.0)),
    "swing-up kappa=1/2": (ocp.swing_up(0.5), lambda: analytic.two_switch("swing-up", 0.5)),
    "swing-up kappa=3/4": (ocp.swing_up(0.75), lambda: analytic.two_switch("swing-up", 0.75)),
}
