"""`ocp bench`: the benchmark suite, the flow of `ocp.solve` run over a grid of cases and methods.

    suite.py        suites as data (benchmarks/*.toml): Case, Method, Suite, load()
    runner.py       references, measurements, scoring, executors (serial, processes, Dask), run()
    peer.py         rockit (optional extra "peer") on the same cases
    store.py        the SQLite results store; CSV and JSON export
    report.py       tables, work-precision charts, performance profiles, failure table
    environment.py  the machine and the versions recorded beside the results
    command.py      `ocp bench` and `ocp report`
"""
