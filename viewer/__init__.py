"""The command line and what a run of simulator.py writes and shows, apart from the physics (which
stays in the flat files). Imports point down: viewer -> simulator -> time_integrator -> energies -> utils.

    startup.py      `python simulator.py` before numpy loads: one BLAS thread, Ctrl+C in one line
    cli.py          the command line: flags, comparisons by lists, one-line errors (exit code 2)
    run.py          a run to files: its plan, signals (Signals, Stopped), the last pictures and its one
                    closing line and exit code (run.end, shared with the window)

    diagnostics.py  what a state says beyond the solver's report: contact speeds, sticking and
                    sliding nodes, the contact forces (from the energies' public functions), inverted cells
    log.py          log.csv: one row per step, appended and flushed as the step ends
    draw.py         one frame: the slope with distance marks, the squares, the forces, a legend; PNG files
    plots.py        plots.png: energy budget, contact speeds, Newton iterations (or a comparison of runs)
    summary.py      summary.png: spaced, time-labelled snapshots at a fixed scale
    page.py         index.html: plays the frames from the file system, with the plots and a time cursor
    files.py        the output folder a run owns: its names, what it refuses, how it writes and removes
    folder_lock.py  one run per folder: the folder's lock, let go however the process ends
    manifest.py     what the runs wrote there and each file's identity (device, inode, size, mtime)
    whole_files.py  files created new (O_EXCL) and written whole, never through a link or blocking
    recording.py    steps one or more scenes side by side and writes all of the above
    window.py       the live window (--window): the run paced to the wall clock, driven by keys down
                    to one Newton iteration, drawn by draw.py, its files (--out) by recording.py

pygame is imported only inside the functions that draw (see draw.load_pygame).
"""
