"""The lecture's claims as pictures, each one command: `python -m figures [NAME ...] [--out DIR]`.

    dissipation     friction's power at every step is <= 0: it takes kinetic energy out, never gives it back
    mollifier       f1 replaces Coulomb's f (C^1 static-dynamic transition); f0'(y) = f1(y / hhat), checked
    semi_implicit   the lagged (semi-implicit) friction against Algorithm 5's fully implicit friction, and
                    which is nearer a reference run at h/8
    fixed_point     Algorithm 5's line-3 measure per friction update: a step that converges, one that does not
    stick_slip      Rabinowicz's chalk: the mark (Archard's law) of the pushed chalk (dashes)
                    and the dragged (a line), the slip length against the grip, and with one
                    coefficient sliding below, jamming above the self-locking angle 90 deg - atan mu

Each figure is a module with `compute(...)` (the numbers, from the project's own functions; the tests
run it on a small case) and `draw(result)` (a `page.Page` of viewer/pictures/plots.py panels). The lecture's mu
comparison is `python simulator.py --mu 0.1,0.11,0.2`, not repeated here. This file imports nothing:
`python -m figures` sets OPENBLAS_NUM_THREADS in __main__.py before numpy loads.
"""
FIGURES = ("dissipation", "mollifier", "semi_implicit", "fixed_point", "stick_slip")     # in the lecture's order
