"""Benchmarks (``make bench``): figures written to bench/out/."""
import limit  # noqa: F401  (sets single-thread BLAS before numpy is loaded)
