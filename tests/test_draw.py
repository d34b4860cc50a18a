"""viewer/draw.py's drawing helpers, one copy each for the frames, plots.png, summary.png and the
window: round numbers (nice_number), arrowheads (arrow_heads), text wrapping (wrap). The chalk's
mark as the frames draw it: tests/test_marks_drawn.py."""
import numpy as np
import pytest

from viewer import draw


@pytest.mark.parametrize("value, down, up", [(0.3, 0.2, 0.5), (7.0, 5.0, 10.0), (1.0, 1.0, 1.0), (2e-5, 2e-5, 2e-5),
                                             (1234.0, 1000.0, 2000.0), (0.0049, 0.002, 0.005)])
def test_nice_number_is_1_2_or_5_times_a_power_of_ten(value, down, up):
    assert draw.nice_number(value) == pytest.approx(down, rel=1e-12)
    assert draw.nice_number(value, up=True) == pytest.approx(up, rel=1e-12)


def test_nice_number_takes_other_steps():
    """The Newton view's zooms (1, 2, 3 or 5 times a power of ten) and summary.png's two digits."""
    assert [draw.nice_number(v, (1, 2, 3, 5)) for v in (4.0, 31.0, 7000.0)] == [3.0, 30.0, 5000.0]
    assert [draw.nice_number(v, range(10, 100)) for v in (38.79, 0.5432, 99.99, 1234.0)] == [38.0, 0.54, 99.0, 1200.0]


def test_arrow_heads_sit_behind_the_tip_on_either_side():
    tail, head = np.array([[0.0, 0.0], [5.0, 5.0]]), np.array([[10.0, 0.0], [5.0, 5.0]])
    corners = draw.arrow_heads(tail, head, 4.0)
    assert corners.shape == (2, 2, 2)
    assert sorted(corners[0].tolist()) == [[6.0, -2.0], [6.0, 2.0]]
    assert np.array_equal(corners[1], [[5.0, 5.0], [5.0, 5.0]])          # an arrow of no length: its tip


def test_wrap_breaks_at_spaces_within_the_width():
    class Font:                                                         # 10 px a character
        def size(self, text):
            return 10 * len(text), 12
    assert draw.wrap(Font(), "space: play   r: restart", 120) == ["space: play", "r: restart"]
    assert draw.wrap(Font(), "a_very_long_word fits", 50) == ["a_very_long_word", "fits"]
