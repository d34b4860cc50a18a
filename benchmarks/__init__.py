"""Supporting scripts: reports and benchmarks run from the repository root as python -m benchmarks.<name>."""
