"""plots.png: panels on one shared time axis, so that the page draws one cursor across them; what
each shows, for the square and the chalk, one run or a comparison: docs/output.md."""
import math

import numpy as np

from analysis import closing, diagnostics, log, stick_slip
from viewer.pictures import draw, wrap

WIDTH, PANEL_HEIGHT, TOP = 900, 250, 10
LEFT, RIGHT = 80, 700           # the time axis's pixel columns; the legends sit right of it
LEGEND_TEXT = RIGHT + 34        # the column where a legend's text starts
ENERGY_COLORS = {"kinetic": (230, 120, 0), "gravity": (120, 80, 40), "spring": (0, 150, 60),
                 "barrier": (200, 0, 160), "hand": (0, 150, 200), "total": (0, 0, 0),
                 "W_friction": (0, 0, 255), "W_hand": (120, 0, 200), "-D_numerical": (200, 0, 0),
                 "W_surface": (0, 170, 170), "-heat": (128, 128, 0), "W_lift": (240, 100, 160)}
ENERGY_LABELS = {"total": "total E", "W_friction": "friction work W", "W_hand": "hand work W_hand",
                 "-D_numerical": "-D, numerical dissip.", "W_surface": "surface work W_surface",
                 "-heat": "-heat, cloth's frame", "W_lift": "lift work W_lift"}
CHALK_PANELS = 4                    # one run's and a comparison's
NORMAL_FORCE_COLOR = (219, 0, 0)    # draw.NORMAL_COLOR, as the frames' arrows
DRIVE_COLOR, BLACK = (0, 150, 60), (0, 0, 0)    # the drive: one run's, a comparison's
EPSV_COLOR, GRID = (200, 0, 0), (225, 225, 225)
SPREAD = 10                 # a comparison's normal forces on a log axis where peaks differ more


def nice_ticks(lo, hi, count=5):
    """Round tick values (1, 2 or 5 times a power of ten apart) covering [lo, hi]."""
    step = draw.nice_number((hi - lo if hi > lo else 1.0) / count, up=True)
    return step * np.arange(math.ceil(lo / step), math.floor(hi / step) + 1)


class Axes:
    """One panel: (t, y) to pixels, y linear or log10; its title, box, ticks and axis labels
    (`xlabel` along, `ylabel` up); t from t_lo to t_max; `yticks`, (value, text), name rows."""

    def __init__(self, pygame, surface, font, top, t_max, y_lo, y_hi, title, ylabel, log=False,
                 xlabel="t (s)", t_lo=0.0, yticks=None, height=PANEL_HEIGHT):
        self.pygame, self.surface, self.font = pygame, surface, font
        self.log, self.yticks = log, yticks
        self.panel_top, self.top, self.bottom = top, top + 24, top + height - 30
        self.t_lo, self.t_max = t_lo, t_max if t_max > t_lo else t_lo + 1.0
        if log:
            y_lo, y_hi = math.log10(y_lo), math.log10(y_hi)
        if not y_hi > y_lo:
            y_lo, y_hi = y_lo - 1.0, y_hi + 1.0
        pad = 0.05 * (y_hi - y_lo)
        self.y_lo, self.y_hi = y_lo - pad, y_hi + pad
        self.legend_row = self.top
        surface.blit(font.render(title, True, BLACK), (LEFT, top + 4))
        box = (LEFT, self.top, RIGHT - LEFT + 1, self.bottom - self.top + 1)
        pygame.draw.rect(surface, BLACK, box, 1)
        self.ticks()
        surface.blit(font.render(xlabel, True, BLACK), (RIGHT + 12, self.bottom + 3))
        label = pygame.transform.rotate(font.render(ylabel, True, BLACK), 90)
        surface.blit(label, (4, (self.top + self.bottom - label.get_height()) / 2))

    def px(self, t, y):
        """Pixel columns and rows (float arrays) of times t and values y."""
        y = np.asarray(y, dtype=float)
        if self.log:
            y = np.log10(np.maximum(y, 10.0 ** self.y_lo))
        t = np.asarray(t, dtype=float)
        col = LEFT + (RIGHT - LEFT) * (t - self.t_lo) / (self.t_max - self.t_lo)
        row = self.bottom - (self.bottom - self.top) * (y - self.y_lo) / (self.y_hi - self.y_lo)
        return col, row

    def ticks(self):
        for t in nice_ticks(self.t_lo, self.t_max, 6):
            col = self.px(t, 0.0)[0]
            self.pygame.draw.line(self.surface, GRID, (col, self.top + 1), (col, self.bottom - 1))
            label = self.font.render(f"{t:g}", True, BLACK)
            self.surface.blit(label, (col - label.get_width() / 2, self.bottom + 3))
        if self.yticks is not None:
            values, texts = zip(*self.yticks)
        elif self.log:
            values = 10.0 ** np.arange(math.ceil(self.y_lo), math.floor(self.y_hi) + 1)
            texts = [f"1e{int(round(math.log10(v)))}" for v in values]
        else:
            values = nice_ticks(self.y_lo, self.y_hi, 4)
            texts = [f"{v:g}" for v in values]
        for value, text in zip(values, texts):
            row = self.px(0.0, value)[1]
            self.pygame.draw.line(self.surface, GRID, (LEFT + 1, row), (RIGHT - 1, row))
            label = self.font.render(text, True, BLACK)
            self.surface.blit(label, (LEFT - 6 - label.get_width(), row - label.get_height() / 2))

    def line(self, t, y, color, width=2):
        if len(t) > 1:
            col, row = self.px(t, y)
            points = np.stack([col, row], 1).tolist()
            self.pygame.draw.lines(self.surface, color, False, points, width)

    def dots(self, t, y, color):
        """A 2x2-pixel dot at each (t, y), written into the surface's pixels at once."""
        col, row = (a.astype(int) for a in self.px(t, y))
        pixels = self.pygame.surfarray.pixels3d(self.surface)
        for dc, dr in ((0, 0), (0, 1), (1, 0), (1, 1)):
            pixels[col + dc, row + dr] = color
        del pixels

    def hline(self, y, color, text):
        row = self.px(0.0, y)[1]
        self.pygame.draw.line(self.surface, color, (LEFT + 1, row), (RIGHT - 1, row), 1)
        self.legend(color, text)

    def vline(self, t, color, text):
        """A dashed vertical line at time t, with a legend row."""
        col = int(self.px(t, 1.0)[0])
        for top in range(self.top + 2, self.bottom - 2, 8):
            end = min(top + 4, self.bottom - 2)
            self.pygame.draw.line(self.surface, color, (col, top), (col, end), 2)
        self.legend(color, text)

    def markers(self, t, y, color, radius=3):
        """A filled circle of `radius` pixels at each (t, y): points that stand alone."""
        for col, row in zip(*self.px(t, y)):
            self.pygame.draw.circle(self.surface, color, (round(col), round(row)), radius)

    def height_needed(self):
        """The panel's height that holds its legend above its time axis's label."""
        return self.legend_row - self.panel_top + 30 - 3

    def legend(self, color, text):
        self.pygame.draw.rect(self.surface, color, (RIGHT + 12, self.legend_row + 5, 16, 6))
        self.note(text)

    def note(self, text):
        """A legend row of text alone, under the last one's."""
        self.surface.blit(self.font.render(text, True, BLACK), (LEGEND_TEXT, self.legend_row))
        self.legend_row += 18

    def runs(self, tracks, data, key, width=2):
        """Each run's d[key] over time as a line in its colour, labelled in the legend."""
        for tr, d in zip(tracks, data):
            self.line(d["t"], d[key], tr.color, width)
            self.legend(tr.color, tr.label)


def series(track):
    """The arrays the plots need from a track's samples: log.csv's columns by name (log.COLUMN),
    the contact nodes' speeds, and the centre of mass's displacement along the slope."""
    s = track.samples.all()

    def column(name):
        return np.array([log.COLUMN[name].value(x) for x in s])
    com = np.stack([column("com_x"), column("com_y")], axis=1)
    terms = ("kinetic",) + diagnostics.energy_terms(track.scene) + ("total",)
    hand = track.scene.hand is not None
    chalk = ("W_hand", "tip_speed", "drive_speed", "normal_force") if hand else ()
    cloth = ("surface_work", "heat") if track.scene.surface is not None else ()
    return {"t": column("t"), "E": {k: column(f"E_{k}") for k in terms},
            "W": column("W_friction"), "D": column("D_numerical"),
            "newton": column("newton_iterations"), "W_hand": None,
            "W_lift": column("W_lift") if track.scene.pushed is not None else None,
            **{k: column(k) for k in chalk},
            **{k: np.array([getattr(x, k) for x in s]) for k in cloth},
            "along": np.array([(c - com[0]) @ track.tangent for c in com]),
            "speed_t": np.concatenate([np.full(len(x.speeds), x.t) for x in s]),
            "speed": np.concatenate([x.speeds for x in s]),
            "max_speed": np.array([x.speeds.max() if len(x.speeds) else np.nan for x in s])}


def speed_range(speeds, epsv):
    """A log axis from a decade below min(eps_v, the least speed > 0), but at most 7 decades below
    eps_v (slower is drawn on the bottom edge), up to the largest speed."""
    shown = np.append(speeds[speeds > 1e-6 * epsv], epsv)
    lo, hi = float(shown.min()), float(shown.max())
    return 10.0 ** math.floor(math.log10(lo) - 1), 10.0 ** math.ceil(math.log10(hi))


def draw_plots(pygame, tracks):
    """plots.png's surface, and the time axis as the page needs it: (left px, right px, t_max).
    Panels are PANEL_HEIGHT tall; one whose legend would run into the next grows to hold it (the
    plots drawn again)."""
    font = pygame.font.Font(None, 18)
    chalk = tracks[0].scene.hand is not None
    data = [series(tr) for tr in tracks]
    t_max = max(float(d["t"][-1]) for d in data)
    heights = [PANEL_HEIGHT] * (CHALK_PANELS if chalk else 3)
    for _ in range(2):                  # the legends' rows do not depend on the heights
        surface = pygame.Surface((WIDTH, TOP + sum(heights)))
        surface.fill(draw.WHITE)
        tops, panels = iter(TOP + np.cumsum([0] + heights[:-1])), []

        def axes(*args, **kw):
            """The next panel down: Axes(y_lo, y_hi, title, ylabel, ...) over [0, t_max]."""
            panels.append(Axes(pygame, surface, font, int(next(tops)), t_max, *args,
                               height=heights[len(panels)], **kw))
            return panels[-1]
        (chalk_panels if chalk else square_panels)(axes, tracks, data)
        needed = [max(height, ax.height_needed()) for height, ax in zip(heights, panels)]
        if needed == heights:
            break
        heights = needed
    return surface, (LEFT, RIGHT, t_max)


def square_panels(axes, tracks, data):
    """One run: its energy budget, each contact node's speed, Newton iterations; a comparison: the
    displacement, the largest contact speed, Newton iterations, one colour per run."""
    epsv = tracks[0].scene.epsv
    cloth = tracks[0].scene.surface is not None         # speeds relative to it (v_p - v_s)
    speed, along = ("relative speed v_p - v_s", "the table") if cloth else ("tangential speed",
                                                                              "the slope")
    if tracks[0].scene.pushed is not None:             # relative to pushed surfaces
        speed, along = "relative speed v_p - v_s", "the lift"
    if len(tracks) == 1:
        (tr,), (d,) = tracks, data
        energy_panel(axes, d)
        ax = axes(*speed_range(d["speed"], epsv), f"{speed} of each contact node (m/s, "
                  "log): below eps_v it sticks", "|v_t| (m/s)", log=True)
        ax.dots(d["speed_t"], d["speed"], tr.color)
        ax.legend(tr.color, "a contact node")
        mark_rest(ax, tr, BLACK)
    else:
        ax = axes(min(d["along"].min() for d in data), max(d["along"].max() for d in data),
                  f"displacement of the centre of mass along {along} (m)", "s (m)")
        ax.runs(tracks, data, "along")
        speeds = np.concatenate([d["speed"] for d in data])
        ax = axes(*speed_range(speeds, epsv), f"largest {speed} of a contact node (m/s, "
                  "log)", "max |v_t| (m/s)", log=True)
        for tr, d in zip(tracks, data):
            has = ~np.isnan(d["max_speed"])
            ax.dots(d["t"][has], d["max_speed"][has], tr.color)
            ax.legend(tr.color, tr.label)
        for tr in tracks:
            mark_rest(ax, tr, tr.color)
    ax.hline(epsv, EPSV_COLOR, f"eps_v = {epsv:g} m/s")
    ax = axes(0.0, max(float(d["newton"].max()) for d in data), "Newton iterations per step",
              "iterations")
    for tr, d in zip(tracks, data):
        ax.line(d["t"][1:], d["newton"][1:], tr.color, 1)
        if len(tracks) > 1:
            ax.legend(tr.color, tr.label)


def chalk_panels(axes, tracks, data):
    """One run: the energy budget, the tip against the drive, the normal force, the cycles; a
    comparison: the last three (forces on a log axis past SPREAD-fold), the friction work."""
    one = len(tracks) == 1
    if one:
        energy_panel(axes, data[0])
    speeds = np.concatenate([np.concatenate([d["tip_speed"], d["drive_speed"]]) for d in data])
    epsv = tracks[0].scene.epsv
    ax = axes(*speed_range(speeds, epsv), "the tip's speed along the board against the hand's "
              "drive (m/s, log): below eps_v it sticks", "|v_tip| (m/s)", log=True)
    drive = DRIVE_COLOR if one else BLACK
    for d in data:                  # under the tip's dots: a tip sliding with the hand stays seen
        ax.line(d["t"], np.maximum(d["drive_speed"], 10.0 ** ax.y_lo), drive, 2)
    for tr, d in zip(tracks, data):
        ax.dots(d["t"], d["tip_speed"], tr.color)
        ax.legend(tr.color, "tip speed" if one else tr.label)
    ax.legend(drive, "drive speed")
    ax.hline(epsv, EPSV_COLOR, f"eps_v = {epsv:g} m/s")
    peaks = [float(d["normal_force"].max()) for d in data]
    title = "the board's normal force on the chalk (N"
    if min(peaks) > 0 and max(peaks) > SPREAD * min(peaks):
        lo = 10.0 ** math.floor(math.log10(min(peaks)) - 1)
        ax = axes(lo, max(peaks), f"{title}, log: the runs' peaks differ more than {SPREAD}-fold)",
                  "N (N)", log=True)
    else:
        ax = axes(0.0, max(peaks), title + ")", "N (N)")
    if one:
        ax.line(data[0]["t"], data[0]["normal_force"], NORMAL_FORCE_COLOR, 2)
        ax.legend(NORMAL_FORCE_COLOR, "sum of lambda_k")
    else:
        ax.runs(tracks, data, "normal_force", 1)
    cycles_panel(axes, tracks)
    if not one:
        ax = axes(min(float(d["W"].min()) for d in data), 0.0, "the work friction has done, "
                  "W_friction (J, <= 0): a step down at each slip", "W (J)")
        ax.runs(tracks, data, "W")


def cycles_panel(axes, tracks):
    """Each stick-slip cycle (analysis/stick_slip.py) a dot: its slip (mm) when it starts."""
    counted = [stick_slip.of_track(tr) for tr in tracks]
    lengths = [1e3 * length for r in counted for _, length, _ in r.slips]
    ax = axes(0.0, 1.2 * max(lengths, default=1.0), "each stick-slip cycle's slip (mm) at its "
              "start; legend: cycles, mean slip, period, % of the drive stuck", "slip (mm)")
    for tr, r in zip(tracks, counted):
        if r.slips:
            t, length, _ = (np.array(a) for a in zip(*r.slips))
            ax.markers(t, 1e3 * length, tr.color)
        first, second = cycles_legend(r)
        if len(tracks) == 1:
            ax.legend(tr.color, first)
        elif ax.font.size(f"{tr.label}: {first}")[0] <= WIDTH - LEGEND_TEXT:
            ax.legend(tr.color, f"{tr.label}: {first}")
        else:                                   # a long label: on its own row
            ax.legend(tr.color, tr.label)
            ax.note(first)
        ax.note(second)


def cycles_legend(r):
    """A stick_slip.StickSlip in a legend's two rows: ('25 slips', '1.06 mm, 107 ms, 86 %'), or
    ('no cycle', what the tip did instead)."""
    if not r.driven:
        return "no cycle", f"the drive starts at {r.start:g} s"
    if r.slips:
        n = len(r.slips)
        period = f", {1e3 * r.period:.0f} ms" if n > 1 else ""
        slips = f"{n} slip{'s' if n > 1 else ''}"
        return slips, f"{1e3 * r.length:.2f} mm{period}, {100 * r.stuck:.0f} %"
    if r.start_up is None:
        return "no cycle", "jammed: tip stuck"
    return "no cycle", f"slid from {r.start_up:.2f} s, {100 * r.stuck:.0f} %"


def mark_rest(ax, track, color):
    """The time the track stuck (recording.Track.rest_since), dashed, and how fast it creeps since
    beside the closed form (closing.creep_figures); or that it did not stick. A pushed scene's
    mark and words are its own (its `mark`: a grasp's fit start or drop, its closing words)."""
    if track.scene.pushed is not None:
        when, said = track.scene.pushed.mark(track)
        first, *rows = wrap.phrase_rows(ax.font, said, WIDTH - LEGEND_TEXT, (" ",))
        ax.legend(color, first) if when is None else ax.vline(when, color, first)
        for row in rows:
            ax.note(row)
        return
    if track.rest_since is None:
        ax.legend(color, f"not stuck by {track.t:.2f} s")
        return
    ax.vline(track.rest_since, color, f"sticks from {track.rest_since:.2f} s,")
    measured, exact = closing.creep_figures(track)
    ax.note(f"creeps {measured:.2f} mm/s")
    if exact is not None:
        ax.note(f"(closed form {exact:.2f})")


def energy_panel(axes, d):
    """The energy budget: each term, E, the work W (friction's, the hand's), with a moving surface
    its work and the heat (W_friction = W_surface - heat), and -D."""
    cloth, works = "heat" in d, [k for k in ("W_hand", "W_lift") if d[k] is not None]
    curves = dict(d["E"], W_friction=d["W"], **{k: d[k] for k in works})
    if cloth:
        curves.update({"W_surface": d["surface_work"], "-heat": -d["heat"]})
    curves["-D_numerical"] = -d["D"]
    lo = min(float(c.min()) for c in curves.values())
    hi = max(float(c.max()) for c in curves.values())
    work = "W_surface - heat" if cloth else "W_friction"
    ax = axes(lo, hi, f"energy budget (J): E = E(0) + {work}" + "".join(f" + {k}" for k in works)
              + " - D, D = implicit Euler's numerical dissipation", "E (J)")
    for key, values in curves.items():
        color = ENERGY_COLORS.get(key, draw.PUSHED_COLOR)       # a unit's own term: its colour
        ax.line(d["t"], values, color, 3 if key == "total" else 2)
        ax.legend(color, ENERGY_LABELS.get(key, key))
