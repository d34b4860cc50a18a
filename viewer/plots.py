"""plots.png, drawn with pygame: what explains a run, over time, on one shared time axis.

One run: (1) the energy budget: kinetic, gravity, spring and barrier energy, their total E, the
work friction has done W (cumulative, <= 0) and D = E(0) + W - E, what is left: the energy implicit
Euler's numerical dissipation took out (mostly at the impact), so that E = E(0) + W - D;
(2) the tangential speed of every contact node, on a log axis with eps_v marked: below it a node
sticks, above it slides; (3) Newton iterations per step.
Several runs (a comparison): (1) displacement of the centre of mass along the slope, (2) the
largest tangential speed of a contact node, (3) Newton iterations per step, one colour per run.
The panels share their time axis, so the page (page.py) draws one cursor across all of them.
"""
import math

import numpy as np

from viewer import diagnostics, draw, log

WIDTH, PANEL_HEIGHT, TOP = 900, 250, 10
LEFT, RIGHT = 80, 700           # the time axis's pixel columns; the legends sit right of it
ENERGY_COLORS = {"kinetic": (230, 120, 0), "gravity": (120, 80, 40), "spring": (0, 150, 60),
                 "barrier": (200, 0, 160), "hand": (0, 150, 200), "total": (0, 0, 0), "W_friction": (0, 0, 255),
                 "W_hand": (120, 0, 200), "-D_numerical": (200, 0, 0)}


def nice_ticks(lo, hi, count=5):
    """Round tick values (1, 2 or 5 times a power of ten apart) covering [lo, hi]."""
    step = draw.nice_number((hi - lo if hi > lo else 1.0) / count, up=True)
    return step * np.arange(math.ceil(lo / step), math.floor(hi / step) + 1)


class Axes:
    """One panel: maps (t, y) to pixels, linear or log10 in y, and draws its box, ticks, the axes'
    labels with their units (`xlabel` along the horizontal axis, "t (s)" by default, `ylabel` up the value
    axis) and lines. The horizontal axis runs from t_lo (0 unless given) to t_max; `yticks`, pairs
    (value, text), replaces the value axis's numbers (rows named instead of measured)."""

    def __init__(self, pygame, surface, font, top, t_max, y_lo, y_hi, title, ylabel, log=False, xlabel="t (s)",
                 t_lo=0.0, yticks=None):
        self.pygame, self.surface, self.font, self.log, self.yticks = pygame, surface, font, log, yticks
        self.top, self.bottom = top + 24, top + PANEL_HEIGHT - 30
        self.t_lo, self.t_max = t_lo, t_max if t_max > t_lo else t_lo + 1.0
        if log:
            y_lo, y_hi = math.log10(y_lo), math.log10(y_hi)
        if not y_hi > y_lo:
            y_lo, y_hi = y_lo - 1.0, y_hi + 1.0
        pad = 0.05 * (y_hi - y_lo)
        self.y_lo, self.y_hi = y_lo - pad, y_hi + pad
        self.legend_row = self.top
        surface.blit(font.render(title, True, (0, 0, 0)), (LEFT, top + 4))
        pygame.draw.rect(surface, (0, 0, 0), (LEFT, self.top, RIGHT - LEFT + 1, self.bottom - self.top + 1), 1)
        self._ticks()
        surface.blit(font.render(xlabel, True, (0, 0, 0)), (RIGHT + 12, self.bottom + 3))
        label = pygame.transform.rotate(font.render(ylabel, True, (0, 0, 0)), 90)
        surface.blit(label, (4, (self.top + self.bottom - label.get_height()) / 2))

    def px(self, t, y):
        """Pixel columns and rows (float arrays) of times t and values y."""
        y = np.asarray(y, dtype=float)
        if self.log:
            y = np.log10(np.maximum(y, 10.0 ** self.y_lo))
        col = LEFT + (RIGHT - LEFT) * (np.asarray(t, dtype=float) - self.t_lo) / (self.t_max - self.t_lo)
        row = self.bottom - (self.bottom - self.top) * (y - self.y_lo) / (self.y_hi - self.y_lo)
        return col, row

    def _ticks(self):
        grey, black = (225, 225, 225), (0, 0, 0)
        for t in nice_ticks(self.t_lo, self.t_max, 6):
            col = self.px(t, 0.0)[0]
            self.pygame.draw.line(self.surface, grey, (col, self.top + 1), (col, self.bottom - 1))
            label = self.font.render(f"{t:g}", True, black)
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
            self.pygame.draw.line(self.surface, grey, (LEFT + 1, row), (RIGHT - 1, row))
            label = self.font.render(text, True, black)
            self.surface.blit(label, (LEFT - 6 - label.get_width(), row - label.get_height() / 2))

    def line(self, t, y, color, width=2):
        if len(t) > 1:
            col, row = self.px(t, y)
            self.pygame.draw.lines(self.surface, color, False, np.stack([col, row], 1).tolist(), width)

    def dots(self, t, y, color):
        """A 2x2-pixel dot at each (t, y), written into the surface's pixels at once."""
        col, row = self.px(t, y)
        col, row = col.astype(int), row.astype(int)
        pixels = self.pygame.surfarray.pixels3d(self.surface)
        for dc in (0, 1):
            for dr in (0, 1):
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
            self.pygame.draw.line(self.surface, color, (col, top), (col, min(top + 4, self.bottom - 2)), 2)
        self.legend(color, text)

    def legend(self, color, text):
        self.pygame.draw.rect(self.surface, color, (RIGHT + 12, self.legend_row + 5, 16, 6))
        self.surface.blit(self.font.render(text, True, (0, 0, 0)), (RIGHT + 34, self.legend_row))
        self.legend_row += 18


def series(track):
    """The arrays the plots need from a track's samples: log.csv's columns by name (log.COLUMN), and
    the contact nodes' speeds."""
    s = track.samples.all()

    def column(name):
        return np.array([log.COLUMN[name].value(x) for x in s])
    com = np.stack([column("com_x"), column("com_y")], axis=1)
    terms = ("kinetic",) + diagnostics.energy_terms(track.scene) + ("total",)
    hand = track.scene.hand is not None
    return {"t": column("t"),
            "E": {k: column(f"E_{k}") for k in terms},
            "W": column("W_friction"), "D": column("D_numerical"), "newton": column("newton_iterations"),
            "W_hand": column("W_hand") if hand else None,
            **({k: column(k) for k in ("tip_speed", "drive_speed", "normal_force")} if hand else {}),
            "along": np.array([(c - com[0]) @ track.tangent for c in com]),
            "speed_t": np.concatenate([np.full(len(x.speeds), x.t) for x in s]),
            "speed": np.concatenate([x.speeds for x in s]),
            "max_speed": np.array([x.speeds.max() if len(x.speeds) else np.nan for x in s])}


def speed_range(speeds, epsv):
    """A log axis from a decade below min(eps_v, the smallest speed > 0) up to the largest speed."""
    positive = speeds[speeds > 0]
    lo = min(epsv, positive.min()) if positive.size else epsv
    hi = max(epsv, positive.max()) if positive.size else epsv
    return 10.0 ** math.floor(math.log10(lo) - 1), 10.0 ** math.ceil(math.log10(hi))


def draw_plots(pygame, tracks):
    """plots.png's surface, and the time axis as the page needs it: (left px, right px, t_max)."""
    font = pygame.font.Font(None, 18)
    surface = pygame.Surface((WIDTH, TOP + 3 * PANEL_HEIGHT))
    surface.fill((255, 255, 255))
    data = [series(tr) for tr in tracks]
    t_max = max(float(d["t"][-1]) for d in data)
    epsv = tracks[0].scene.epsv
    if len(tracks) == 1 and tracks[0].scene.hand is not None:
        _energy_panel(pygame, surface, font, TOP, t_max, data[0])
        _chalk_panels(pygame, surface, font, t_max, tracks[0], data[0])
        return surface, (LEFT, RIGHT, t_max)
    if len(tracks) == 1:
        _energy_panel(pygame, surface, font, TOP, t_max, data[0])
        d = data[0]
        ax = Axes(pygame, surface, font, TOP + PANEL_HEIGHT, t_max, *speed_range(d["speed"], epsv),
                  "tangential speed of each contact node (m/s, log): below eps_v it sticks", "|v_t| (m/s)", log=True)
        ax.dots(d["speed_t"], d["speed"], tracks[0].color)
        ax.legend(tracks[0].color, "a contact node")
        mark_rest(ax, tracks[0], (0, 0, 0))
    else:
        ax = Axes(pygame, surface, font, TOP, t_max, min(d["along"].min() for d in data),
                  max(d["along"].max() for d in data), "displacement of the centre of mass along the slope (m)",
                  "s (m)")
        for tr, d in zip(tracks, data):
            ax.line(d["t"], d["along"], tr.color)
            ax.legend(tr.color, tr.label)
        speeds = np.concatenate([d["speed"] for d in data])
        ax = Axes(pygame, surface, font, TOP + PANEL_HEIGHT, t_max, *speed_range(speeds, epsv),
                  "largest tangential speed of a contact node (m/s, log)", "max |v_t| (m/s)", log=True)
        for tr, d in zip(tracks, data):
            has = ~np.isnan(d["max_speed"])
            ax.dots(d["t"][has], d["max_speed"][has], tr.color)
            ax.legend(tr.color, tr.label)
        for tr in tracks:
            mark_rest(ax, tr, tr.color)
    ax.hline(epsv, (200, 0, 0), f"eps_v = {epsv:g} m/s")
    ax = Axes(pygame, surface, font, TOP + 2 * PANEL_HEIGHT, t_max, 0.0,
              max(float(d["newton"].max()) for d in data), "Newton iterations per step", "iterations")
    for tr, d in zip(tracks, data):
        ax.line(d["t"][1:], d["newton"][1:], tr.color, 1)
        if len(tracks) > 1:
            ax.legend(tr.color, tr.label)
    return surface, (LEFT, RIGHT, t_max)


def _chalk_panels(pygame, surface, font, t_max, track, d):
    """The chalk's panels 2 and 3: the tip's speed along the board against the hand's drive speed (log, eps_v
    marked: below it the tip sticks), and the board's normal force, whose saw-tooth is the stick-slip."""
    speeds = np.concatenate([d["tip_speed"], d["drive_speed"]])
    ax = Axes(pygame, surface, font, TOP + PANEL_HEIGHT, t_max, *speed_range(speeds, track.scene.epsv),
              "the tip's speed along the board against the hand's drive (m/s, log): below eps_v it sticks",
              "|v_tip| (m/s)", log=True)
    ax.dots(d["t"], d["tip_speed"], track.color)
    ax.legend(track.color, "tip speed")
    ax.line(d["t"], np.maximum(d["drive_speed"], 10.0 ** ax.y_lo), (0, 150, 60), 2)
    ax.legend((0, 150, 60), "drive speed")
    ax.hline(track.scene.epsv, (200, 0, 0), f"eps_v = {track.scene.epsv:g} m/s")
    ax = Axes(pygame, surface, font, TOP + 2 * PANEL_HEIGHT, t_max, 0.0, float(d["normal_force"].max()),
              "the board's normal force on the chalk (N)", "N (N)")
    ax.line(d["t"], d["normal_force"], NORMAL_FORCE_COLOR, 2)
    ax.legend(NORMAL_FORCE_COLOR, "sum of lambda_k")


NORMAL_FORCE_COLOR = (219, 0, 0)    # draw.NORMAL_COLOR, as the frames' arrows


def mark_rest(ax, track, color):
    """The time the track came to rest (recording.Track.rest_since), dashed, or that it did not."""
    if track.rest_since is not None:
        ax.vline(track.rest_since, color, f"at rest from {track.rest_since:.2f} s")
    else:                               # never at rest: said in its legend, no line
        ax.legend(color, f"not at rest by {track.t:.2f} s")


def _energy_panel(pygame, surface, font, top, t_max, d):
    curves = dict(d["E"], W_friction=d["W"], **({} if d["W_hand"] is None else {"W_hand": d["W_hand"]}),
                  **{"-D_numerical": -d["D"]})
    lo = min(float(c.min()) for c in curves.values())
    hi = max(float(c.max()) for c in curves.values())
    ax = Axes(pygame, surface, font, top, t_max, lo, hi,
              "energy budget (J): E = E(0) + W_friction" + (" + W_hand" if d["W_hand"] is not None else "") +
              " - D, D = implicit Euler's numerical dissipation", "E (J)")
    names = {"kinetic": "kinetic", "gravity": "gravity", "spring": "spring", "barrier": "barrier", "hand": "hand",
             "total": "total E", "W_friction": "friction work W", "W_hand": "hand work W_hand",
             "-D_numerical": "-D, numerical dissip."}
    for key, values in curves.items():
        ax.line(d["t"], values, ENERGY_COLORS[key], 3 if key == "total" else 2)
        ax.legend(ENERGY_COLORS[key], names[key])
