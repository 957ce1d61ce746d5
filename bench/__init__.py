"""Benchmarks (``make bench``): figures written to bench/out/."""
