"""The command line and the run, from `python simulator.py [flags]` to its closing line."""
