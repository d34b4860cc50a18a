"""What a run of simulator.py writes and shows, apart from the physics and its analysis (analysis/):

    command/   the command line and the run: flags, signals, progress, exit codes, frames' process
    demo/      the live window (--window), down to one Newton iteration
    pictures/  pictures written to files: frames, plots.png, summary.png, the page
    output/    a run's folder and files written whole

Imports point one way: demo -> command -> pictures -> output -> analysis -> simulator.
"""
