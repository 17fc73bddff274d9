"""Design-space exploration: a scene's keys varied over ranges, lists and distributions, every design run
through the scene pipeline, the results streamed to Parquet (``camcad sweep``).

Modules, one concept each: ``space`` (keys, SPECs, design ids, a design's scene), ``evaluate`` (one design →
one row of check figures; a chunk of designs: the unit of work), ``store`` (Parquet chunks, the manifest that
resumes a sweep), ``engine`` (this process, a local process pool, a Dask cluster), ``run`` (check, chunk and
run a sweep) and ``analysis`` (counts, governing limits, the feasible boundary, the Pareto front, the best
design). Plots and files of a sweep: ``camcad.report.sweep``.
"""

from __future__ import annotations
