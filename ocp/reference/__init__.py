"""The reference set: benchmark instances with certified global optima, as plain files in
`reference/` (read here), their generation (`generate`, `multiprecision`), and `score`, which scores a
solution from any tool against its instance."""

from .data import folder, load, lookup

__all__ = ["folder", "load", "lookup"]
