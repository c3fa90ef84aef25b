"""Exact references: closed forms and quadratures of the torque-limited pendulum (`finch`)."""
