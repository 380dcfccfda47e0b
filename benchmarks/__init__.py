"""Speed and memory benchmarks. Run all with ``make bench`` (``python -m benchmarks``) or one
with ``python -m benchmarks NAME``. Each ``bench_*.py`` module defines ``run() -> list[dict]``;
every dict is one row of the printed table (include the target and whether it is met)."""
