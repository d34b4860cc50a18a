"""python -m figures: one BLAS thread (set before numpy loads, as simulator.py does), then figures.cli."""
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

try:
    from figures import cli
    code = cli.main()
except KeyboardInterrupt:       # Ctrl+C while numpy and scipy load, before cli.main handles it
    print("figures: stopped: interrupted", file=sys.stderr)
    code = 130
sys.exit(code)
