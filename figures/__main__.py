"""python -m figures: one BLAS thread, and Ctrl+C while numpy loads in one line (viewer/command/startup.py, as
`python simulator.py`), then figures.cli."""
import sys

from viewer.command import startup

sys.exit(startup.run_command_line(program="figures", main="figures.cli"))
