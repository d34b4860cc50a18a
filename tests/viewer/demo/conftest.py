"""Each window test starts without a display: one test's window (its size, the events SDL queued
for it, e.g. WindowSizeChanged after set_mode) never reaches the next test in the same worker."""
import sys

import pytest


@pytest.fixture(autouse=True)
def no_display_left():
    """After the test, pygame's display quit (SDL's window and its event queue with it)."""
    yield
    pygame = sys.modules.get("pygame")
    if pygame is not None and pygame.display.get_init():
        pygame.display.quit()
