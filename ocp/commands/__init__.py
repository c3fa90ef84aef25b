"""The commands of the command line, a module each (asv's `commands/` is the model): `add_commands(sub)`
registers its parsers, `run(args)` returns the exit status. `ocp.cli` only dispatches to them."""
