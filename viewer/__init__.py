"""The command line and what a run of simulator.py writes and shows, apart from the physics (the
flat files) and the analysis of its states (analysis/). One job per package; imports point one way:

    command/   the command line and the run: flags, the run's folder, signals, progress, exit codes
    demo/      the live window (--window), down to one Newton iteration
    pictures/  pictures written to files: frames, plots.png, summary.png, the page
    output/    a run's folder and files written whole

demo -> command -> pictures -> output -> analysis -> simulator. pygame is imported only inside the
functions that draw (see pictures.draw.load_pygame).
"""
