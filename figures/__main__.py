"""python -m figures: one BLAS thread and Ctrl+C set up before numpy loads, then figures.cli."""
import sys

from viewer.command import startup

sys.exit(startup.run_command_line(program="figures", main="figures.cli"))
