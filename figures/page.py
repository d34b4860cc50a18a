"""What every figure shares: a white page with a title, panels of viewer/pictures/plots.py stacked on one axis
width, and a caption of measured numbers under them, as PNG bytes (viewer/pictures/draw.py)."""
from viewer.pictures import draw, plots

TITLE_HEIGHT, LINE_HEIGHT = 34, 19      # pixels
BLACK, GREY, RED = (0, 0, 0), (120, 120, 120), (220, 0, 0)


class Page:
    """`panels` plots.Axes, one under the other, under `title`; `caption` (lines of text) at the bottom."""

    def __init__(self, title, panels, caption):
        self.pygame = pygame = draw.load_pygame()
        self.font = pygame.font.Font(None, 18)
        self.surface = pygame.Surface((plots.WIDTH, TITLE_HEIGHT + panels * plots.PANEL_HEIGHT
                                       + LINE_HEIGHT * (len(caption) + 1)))
        self.surface.fill((255, 255, 255))
        self.surface.blit(pygame.font.Font(None, 26).render(title, True, BLACK), (12, 10))
        top = TITLE_HEIGHT + panels * plots.PANEL_HEIGHT
        for i, line in enumerate(caption):
            self.surface.blit(pygame.font.Font(None, 20).render(line, True, BLACK), (12, top + i * LINE_HEIGHT))

    def axes(self, panel, x_max, y_lo, y_hi, title, xlabel, ylabel, log=False, x_lo=0.0, yticks=None):
        """Panel number `panel` (0 at the top): x from x_lo (0 unless given) to x_max, y from y_lo to y_hi
        (log10 if log; `yticks`, pairs (value, text), to name rows instead), the axes labelled with their units."""
        return plots.Axes(self.pygame, self.surface, self.font, TITLE_HEIGHT + panel * plots.PANEL_HEIGHT,
                          x_max, y_lo, y_hi, title, ylabel, log, xlabel, x_lo, yticks)

    def markers(self, ax, x, y, color, radius=3):
        """A filled circle of `radius` pixels at each (x, y) of the panel `ax`: points that stand out on a line."""
        for col, row in zip(*(a.tolist() for a in ax.px(x, y))):
            self.pygame.draw.circle(self.surface, color, (col, row), radius)

    def png(self):
        """The page as 24-bit PNG bytes."""
        return draw.png_data(self.pygame, self.surface, exact=True)
