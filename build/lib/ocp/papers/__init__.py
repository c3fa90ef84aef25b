"""The papers the suite is built on: their printed values (`data/*.toml`, read by `references`),
the suite's computation of each (`finch2015`, `batista2006`, `weinstein_tam`), and `verify`, which
sets them side by side."""
