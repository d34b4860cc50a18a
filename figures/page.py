"""A figure's page: a title, panels of viewer/pictures/plots.py stacked on one axis width, and a
caption of measured numbers under them, as PNG bytes."""
from viewer.pictures import draw, plots

TITLE_HEIGHT, LINE_HEIGHT = 34, 19      # pixels
BLACK, GREY, RED = (0, 0, 0), (120, 120, 120), (220, 0, 0)


class Page:
    """`panels` plots.Axes one under the other, under `title`; the `caption` lines at the bottom."""

    def __init__(self, title, panels, caption):
        self.pygame = pygame = draw.load_pygame()
        self.font = pygame.font.Font(None, 18)
        top = TITLE_HEIGHT + panels * plots.PANEL_HEIGHT
        self.surface = pygame.Surface((plots.WIDTH, top + LINE_HEIGHT * (len(caption) + 1)))
        self.surface.fill((255, 255, 255))
        self.surface.blit(pygame.font.Font(None, 26).render(title, True, BLACK), (12, 10))
        font = pygame.font.Font(None, 20)
        for i, line in enumerate(caption):
            self.surface.blit(font.render(line, True, BLACK), (12, top + i * LINE_HEIGHT))

    def axes(self, panel, x_max, y_lo, y_hi, title, xlabel, ylabel, log=False, x_lo=0.0,
             yticks=None):
        """Panel `panel` (0 at the top): x from x_lo to x_max, y from y_lo to y_hi (log10 if log;
        `yticks`, pairs (value, text), name rows instead)."""
        top = TITLE_HEIGHT + panel * plots.PANEL_HEIGHT
        return plots.Axes(self.pygame, self.surface, self.font, top, x_max, y_lo, y_hi, title,
                          ylabel, log, xlabel, x_lo, yticks)

    def png(self):
        """The page as 24-bit PNG bytes."""
        return draw.png_data(self.pygame, self.surface)
