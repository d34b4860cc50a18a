"""The live window (`--window`), for an instructor's demo: a step or one Newton iteration at a time.

    live.py         the demo without its window (no pygame): the run a step or a Newton iteration
                    at a time, paced to the wall clock, the keys, its files (--out) and warnings
    window.py       the window: the loop (keys, status, drawing), opening the display
    newton_view.py  the Newton view: the iterate, the direction p, the magnified inset
"""
