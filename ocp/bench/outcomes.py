"""The outcome classes of a benchmark row, declared once: every module (scoring, the store, the
report, the failure maps and their figures) reads this table. Adding an outcome is one line here
(and the branch of `ocp.bench.scoring.outcome` that returns it).

Each member is its label (a str: it is stored, counted and printed as such) and carries

    rank        its place in the order of classification (`scoring.outcome` tries the classes
                in this order: the first that applies is the row's)
    success     whether it counts as reaching the optimum
    structure   "optimal" (the optimal extremal's structure and branch, accurate or not),
                "another" (a converged answer on another extremal), or "" (no answer to place)
    colour, marker         its style in the failure maps (`ocp.figures.failure_map`): a colour of
                           its own, shared with no other outcome and no switch count of the map
                           under it (`ocp.figures.synthesis.COUNT_COLOURS`)
    open_marker            its open marker in the work-precision charts ("another" only)

The order of the members is the index order of saved failure maps (`failure_map.save`): append,
never reorder.
"""

import enum


class Outcome(enum.StrEnum):
    """The class of a benchmark row (module doc)."""

    def __new__(cls, label, rank, success, structure, colour, marker, open_marker=""):
        member = str.__new__(cls, label)
        member._value_ = label
        member.rank, member.success, member.structure = rank, success, structure
        member.colour, member.marker, member.open_marker = colour, marker, open_marker
        return member

    #                label              rank success structure colour    marker open
    OK = "ok", 7, True, "optimal", "#2ca02c", "o"
    BUILD_ERROR = "build error", 0, False, "", "#969696", "+"
    TIME_LIMIT = "time limit", 1, False, "", "#ffd92f", "+"
    INACCURATE = "inaccurate", 9, False, "optimal", "#01665e", "d"
    LOCAL_OPTIMUM = "local optimum", 10, False, "another", "#d62728", "s", "o"
    WRONG_STRUCTURE = "wrong structure", 12, False, "another", "#e7298a", "D", "s"
    BEYOND_HORIZON = "beyond horizon", 11, False, "another", "#8c564b", "^", "^"
    CHATTERING = "chattering", 6, False, "", "#f781bf", "P"
    MISSES_TARGET = "misses target", 5, False, "", "#17becf", "X"
    NOT_CONVERGED = "not converged", 4, False, "", "#525252", "x"
    SOLVER_ERROR = "solver error", 3, False, "", "#bcbd22", "x"
    NO_REFERENCE = "no reference", 2, False, "", "#a50026", "v"
    DISCRETISATION = "discretisation", 8, True, "optimal", "#a6d854", "o"


#: the labels, in index order (failure maps store indices into this)
OUTCOMES = tuple(Outcome)
#: converged to the optimal structure (accurate or not), and to another extremal
GOOD = tuple(o for o in Outcome if o.structure == "optimal")
ANOTHER = tuple(o for o in Outcome if o.structure == "another")
