"""The command line and the run: `python simulator.py [flags]` from its first line to its last.

    startup.py      before numpy loads: one BLAS thread, Ctrl+C in one line
    cli.py          the flags, comparisons by lists, one-line errors (exit code 2)
    run.py          a run to files: its plan, signals (Signals, Stopped), the last pictures and
                    its one closing line and exit code (run.end, shared with the window)
    recording.py    the run driver: steps scenes side by side, a log row as each step ends
    progress.py     what a run says as it goes: progress lines, warnings about a step
"""
