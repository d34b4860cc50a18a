"""The command line and what a run of simulator.py writes and shows, apart from the physics (which
stays in the flat files). Imports point down: viewer -> simulator -> time_integrator -> energies -> utils.

    startup.py      `python simulator.py` before numpy loads: one BLAS thread, Ctrl+C in one line
    cli.py          the command line: flags, comparisons by lists, one-line errors (exit code 2)
    run.py          a run to files: its plan, signals (Signals, Stopped), the last pictures and its one
                    closing line and exit code (run.end, shared with the window)

    diagnostics.py  what a state says beyond the solver's report: contact speeds, sticking and
                    sliding nodes, the contact forces (from the energies' public functions), inverted cells
    log.py          log.csv: one row per step, appended and flushed as the step ends
    recording.py    the run driver: steps one or more scenes side by side, a log row as each step ends
    progress.py     what a run says as it goes: progress lines, warnings about a step, what it showed (when
                    the square came to rest, the chalk's stick-slip)
    stick_slip.py   the chalk's stick-slip cycles counted on its tip, once for the run, figures and tests
    frames.py       when each frame is due; writing it (PNG, OBJs, the page's figures)
    draw.py         one frame: the slope with distance marks, the squares, the forces, a legend; PNG
                    files; the drawing helpers (arrowheads, text wrapping, round numbers)
    marks.py        the chalk's mark on the board by Archard's law (marks.csv), drawn grey at the
                    picture's scale and in a strip magnified x8
    plots.py        plots.png: energy budget, contact speeds, Newton iterations (or a comparison of runs);
                    the chalk's tip against the drive, normal force, stick-slip cycles
    summary.py      summary.png: spaced, time-labelled snapshots at a fixed scale
    page.py         index.html: plays the frames from the file system, with the plots and a time cursor
    pictures.py     what a run writes at its end: the chalk's marks.csv, summary.png, plots.png,
                    index.html
    files.py        a run's folder: new (or an empty --out), its names, each file written whole
    whole_files.py  files created new (O_EXCL) and written whole, never through a link
    live.py         the live demo without its window (no pygame): the run a step or a Newton iteration
                    at a time, paced to the wall clock, what the keys do, its files (--out) and warnings
    newton_view.py  the window's Newton view: the iterate, the direction p, the magnified inset
    window.py       the live window (--window): the loop (keys, status, drawing), opening the display

pygame is imported only inside the functions that draw (see draw.load_pygame).
"""
