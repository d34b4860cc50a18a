"""plots.png's axes carry their units: "t (s)" at the end of every time axis, the quantity and its unit
up every value axis (the panels' titles name them too)."""
import numpy as np

import simulator
from helpers.command import recorded as tracks_of
from viewer import draw, plots


def test_every_panel_labels_its_time_axis_and_its_value_axis(tmp_path):
    pygame = draw.load_pygame()
    surface, _ = plots.draw_plots(pygame, tracks_of(tmp_path, [simulator.build_scene()], 30))
    dark = np.all(pygame.surfarray.array3d(surface) < 100, axis=2)                     # [x, y]: text
    for panel in range(3):
        top, bottom = plots.TOP + panel * plots.PANEL_HEIGHT + 24, plots.TOP + (panel + 1) * plots.PANEL_HEIGHT - 30
        assert dark[plots.RIGHT + 12:plots.RIGHT + 50, bottom + 3:bottom + 18].any(), f"panel {panel}: t (s)"
        assert dark[:22, top:bottom].any(), f"panel {panel}: the value axis"
