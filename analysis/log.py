"""log.csv: one row per step (and one for t = 0), appended and flushed as each step ends.

COLUMN defines each per-step figure once: its name (log.csv's header, a row's key), unit ("" for a
count or a flag), label (a table's header), meaning, format spec, `value(sample)` (None: an empty
field) and `applies(scene)` (None: every scene logs it). log.csv (`line`), the page and plots.png
read the same named rows (`values`); docs/output.md's table is COLUMN as written here.
"""
from collections import namedtuple

from scenes import UNITS

Column = namedtuple("Column", "name unit label meaning fmt value applies", defaults=[None])


def with_hand(scene):
    """Whether a scene has a hand (the chalk): its energy, its work and its tip are logged."""
    return "hand" in scene.terms


def with_surface(scene):
    """Whether a scene's contact moves along itself (its `moves`): its speed, the slip and the heat
    logged."""
    return scene.contact is not None and scene.contact.moves


def with_pushed(scene):
    """Whether a scene has the grasp's fingers: their work, and the columns its unit declares."""
    return scene.pushed is not None


def solver(figure, at_start):
    """figure(the step's StepReport), or `at_start` at t = 0, where no step was taken."""
    return lambda s: at_start if s.report is None else figure(s.report)


def energy(term):
    """The state's energy of `term` (diagnostics.energies)."""
    return lambda s: s.energies[term]


COLUMN = {c.name: c for c in [
    Column("step", "", "step", "the steps taken (0: the start)", "d", lambda s: s.step),
    Column("t", "s", "t", "the time after them", ".6f", lambda s: s.t),
    Column("wall_s", "s", "wall time", "the step's wall-clock time", ".6f", lambda s: s.wall),
    Column("com_x", "m", "centre of mass x", "the centre of mass, x", ".9f",
           lambda s: float(s.com[0])),
    Column("com_y", "m", "centre of mass y", "the centre of mass, y", ".9f",
           lambda s: float(s.com[1])),
    Column("v_tangential", "m/s", "velocity along the slope",
           "the centre of mass's velocity along the slope", ".9f", lambda s: s.v_tangential),
    Column("newton_iterations", "", "Newton iterations",
           "Newton iterations of the step, summed over its solves", "d",
           solver(lambda r: r.newton_iterations, 0)),
    Column("residual", "m/s", "residual",
           "||p||_inf / h at the step's end; where the bound ||grad E||_2 / (min m h) already "
           "shows convergence, that bound (an upper bound on ||p||_inf / h)", ".3e",
           solver(lambda r: r.residual, None)),
    Column("newton_stalled", "", "Newton stalled",
           "1 where Newton stopped at float64's round-off floor with the residual above tol", "d",
           solver(lambda r: int(r.stalled), 0)),
    Column("alpha_min", "", "smallest alpha", "the smallest accepted line-search step alpha",
           ".6g", solver(lambda r: min(r.alphas, default=1.0), None)),
    Column("line_search_steps", "", "line searches", "how many line searches", "d",
           solver(lambda r: len(r.alphas), 0)),
    Column("min_distance", "m", "min distance", "the smallest node distance to the slope", ".9g",
           lambda s: s.min_distance),
    Column("friction_updates", "", "friction updates",
           "how many times Algorithm 5 updated mu*lambda at the new iterate and solved the step "
           "again; 0 for the lecture's lagged friction (the default) and without friction, at most "
           "--friction-iterations", "d", solver(lambda r: r.friction_updates, 0)),
    Column("friction_converged", "", "friction converged",
           "1 where the step ended at Algorithm 5's fixed point (the Newton residual with the "
           "updated mu*lambda <= tol), 0 where it stopped at the cap above it; always 1 for lagged "
           "friction, which does not iterate", "d", solver(lambda r: int(r.friction_converged), 1)),
    Column("contacts_sticking", "", "contacts sticking",
           "nodes within dhat of the slope whose tangential speed relative to it, "
           "||(I - n n^T)(v - v_s)||, is below eps_v (the mollifier's static regime; v_s = 0 but "
           "on the tablecloth)", "d", lambda s: s.sticking),
    Column("contacts_sliding", "", "contacts sliding",
           "nodes within dhat of the slope at or above eps_v", "d", lambda s: s.sliding),
    Column("inverted_triangles", "", "inverted triangles", "mesh triangles turned over", "d",
           lambda s: s.inverted),
    Column("E_kinetic", "J", "kinetic energy", "the kinetic energy", ".9g", energy("kinetic")),
    Column("E_gravity", "J", "gravity", "gravity's potential energy", ".9g", energy("gravity")),
    Column("E_spring", "J", "spring energy", "the springs' energy", ".9g", energy("spring")),
    Column("E_barrier", "J", "barrier energy", "the barrier's energy", ".9g", energy("barrier")),
    Column("E_hand", "J", "hand energy",
           "the hand's springs' energy, at the targets of the state's time (the chalk)", ".9g",
           energy("hand"), with_hand),
    Column("E_total", "J", "total energy", "their sum, E", ".9g", energy("total")),
    Column("W_friction", "J", "friction work",
           "the work friction has done since t = 0 (<= 0 on a still surface), summed over steps as "
           "-grad P_f . (x^{n+1} - x^n)", ".9g", lambda s: s.friction_work),
    Column("W_hand", "J", "hand work",
           "the work the hand's moving targets have done on its springs since t = 0, summed over "
           "steps as P_hand(x^n, targets(t^{n+1})) - P_hand(x^n, targets(t^n)) (the chalk)", ".9g",
           lambda s: s.hand_work, with_hand),
    Column("W_lift", "J", "lift work",
           "the work that has held the fingers on their prescribed path since t = 0, summed over "
           "steps as the force along it, (grad E) . t / h^2 on their rows, times their motion",
           ".9g", lambda s: s.contact_work, with_pushed),
    Column("D_numerical", "J", "numerical dissipation",
           "E(0) + W_friction - E (+ W_hand with a hand, + W_lift with the fingers), = E(0) + "
           "W_surface - heat - E on the tablecloth: what implicit Euler's numerical dissipation "
           "has taken out", ".9g",
           lambda s: s.numerical_dissipation),
    Column("tip_x", "m", "tip x", "the chalk's tip, its lowest node: x along the board", ".9f",
           lambda s: s.tip_x, with_hand),
    Column("tip_speed", "m/s", "tip speed", "the tip's speed along the board, |v_x|", ".6e",
           lambda s: s.tip_speed, with_hand),
    Column("drive_speed", "m/s", "drive speed",
           "the hand's targets' speed along the board over the last step", ".6e",
           lambda s: s.drive_speed, with_hand),
    Column("normal_force", "N", "normal force",
           "the board's normal force on the chalk, the sum of lambda_k", ".6e",
           lambda s: s.normal_force, with_hand),
    Column("surface_speed", "m/s", "surface speed",
           "the moving surface's velocity v_s along the table (the tablecloth) or the fingers' "
           "path over the last step", ".9f", lambda s: s.surface_speed, with_surface),
    Column("slip_speed", "m/s", "slip speed",
           "the largest tangential speed of a contact node relative to the surface, |t . (v_k - "
           "v_s)|", ".6e", lambda s: float(s.speeds.max(initial=0.0)), with_surface),
    Column("W_surface", "J", "surface work",
           "the work the surface's motion has put in since t = 0, summed over steps as F_f . v_s h",
           ".9g", lambda s: s.surface_work, with_surface),
    Column("heat", "J", "heat",
           "friction's heat since t = 0 (>= 0), W_surface - W_friction: minus friction's work in "
           "the surface's frame, -F_f . (x^{n+1} - x^n - v_s h) summed over steps", ".9g",
           lambda s: s.heat, with_surface),
] + [Column(*c, applies=with_pushed) for unit in UNITS.values() for c in unit.LOG_COLUMNS]}


def columns(scene):
    """The names of a scene's log.csv columns, in order: every column that applies to it."""
    return [name for name, c in COLUMN.items() if c.applies is None or c.applies(scene)]


COLUMNS = [name for name, c in COLUMN.items() if c.applies is None]     # the square's header


def values(sample, names=COLUMNS):
    """A Sample's named row for the columns `names`: {name: its figure, None where none}."""
    return {name: COLUMN[name].value(sample) for name in names}


def line(row):
    """log.csv's line of a named row: each figure in its column's format, empty where None."""
    return ",".join("" if value is None else format(value, COLUMN[name].fmt)
                    for name, value in row.items())
