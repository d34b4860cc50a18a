"""The lecture's claims as pictures (README's figure table), `python -m figures [NAME ...]`: each
a module with `compute(...)`, its numbers from the project's own functions, and `draw(result)`, a
page.Page. This file imports nothing: __main__.py sets up BLAS before numpy loads."""
FIGURES = ("dissipation", "relative_velocity", "mollifier", "semi_implicit", "fixed_point",
           "stick_slip", "grasp")  # as taught
