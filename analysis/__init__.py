"""What a run's states say beyond the solver's report, shared by the tests, the pictures and the
window; no pygame, no files (imports point down: analysis -> simulator -> time_integrator ->
energies).

    diagnostics.py  contact speeds, sticking and sliding nodes, the contact forces (from the
                    energies' public functions), inverted cells, the energy budget, the chalk's tip
    stick_slip.py   the chalk's stick-slip cycles counted on its tip: for the run, figures, tests
    log.py          log.csv's columns: the named figures of one state, as a row
    closing.py      what a run showed, in words: the square's rest, the chalk's stick-slip
    wear.py         the chalk's mark by Archard's law: the deposit per 0.1 mm of board, marks.csv
"""
