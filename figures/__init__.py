"""The lecture's claims as pictures, each one command: `python -m figures [NAME ...] [--out DIR]`.

    dissipation     friction's power is <= 0 at every step: it only takes kinetic energy out
    mollifier       f1 replaces Coulomb's f (a C^1 static-dynamic transition); f0'(y) = f1(y / hhat)
    semi_implicit   lagged against Algorithm 5's implicit friction: which is nearer a run at h/8
    fixed_point     Algorithm 5's line-3 measure per friction update: a step that converges, one not
    stick_slip      Rabinowicz's chalk: the marks pushed (dashes) and dragged (a line), the slip
                    against the grip, and with one coefficient sliding below, jamming above a tilt

Each is a module with `compute(...)` (its numbers, from the project's own functions) and
`draw(result)` (a page.Page). This file imports nothing: __main__.py sets up BLAS first.
"""
FIGURES = ("dissipation", "mollifier", "semi_implicit", "fixed_point", "stick_slip")  # as taught
