"""python -m figures: one BLAS thread (set before numpy loads, as simulator.py does), then figures.cli."""
import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

from figures import cli     # noqa: E402  (after the environment is set)

sys.exit(cli.main())
