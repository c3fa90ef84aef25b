"""The reference set: benchmark instances with certified global optima, as plain files in
`reference/` (read here), their generation (`generate`, `multiprecision`), and `score`, which scores a
solution from any tool against its instance."""

from .data import bench_reference, folder, load, lookup

__all__ = ["bench_reference", "folder", "load", "lookup"]
