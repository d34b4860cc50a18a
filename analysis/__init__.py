"""What a run's states say beyond the solver's report, for the tests, the pictures and the window.
No pygame, no files; imports point down: analysis -> simulator -> time_integrator -> energies.

    diagnostics.py  contact speeds, sticking and sliding, forces, inverted cells, the energy budget
    stick_slip.py   the chalk's stick-slip cycles, counted on its tip
    log.py          log.csv's columns: the named figures of one state, as a row
    closing.py      what a run showed, in words: the square's rest, the chalk's stick-slip
    wear.py         the chalk's mark by Archard's law: the deposit per 0.1 mm of board, marks.csv
"""
