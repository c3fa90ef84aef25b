"""`ocp bench`: the benchmark suite, the flow of `ocp.solve` run over a grid of cases and methods.

    suite.py        suites as data (benchmarks/*.toml): Case, Method, Suite, load()
    outcomes.py     the outcome classes, declared once (label, rank, success, chart style)
    row.py          the typed values: Reference, Measurement, Score, Row (validated when read back)
    reference.py    the search's optimum of a case
    measurement.py  one pair solved: times, peak memory
    scoring.py      a measurement against its reference: T - T_ref and the outcome
    profiles.py     the Dolan-More costs and ratios (drawn in report.py)
    runner.py       run(): references, then every pair through an executor (`ocp.core.parallel`)
    peer.py         rockit (optional extra "peer") on the same cases
    store.py        the SQLite results store; CSV and JSON export
    report.py       tables, work-precision charts, performance profiles, failure table
    environment.py  the machine and the versions recorded beside the results
    command.py      `ocp bench` and `ocp report`
"""
