"""viewer/pictures/draw.py's drawing helpers, one copy each for the frames, plots.png, summary.png
and the window: round numbers (nice_number), arrowheads (arrow_heads); the force arrows' scale.
The chalk's mark as the frames draw it: tests/viewer/pictures/test_marks_drawn.py."""
import itertools

import numpy as np
import pytest

import simulator
from helpers import legibility
from helpers.command import run_main
from analysis import diagnostics
from viewer.pictures import draw, frames


@pytest.mark.parametrize("value, down, up", [
    (0.3, 0.2, 0.5), (7.0, 5.0, 10.0), (1.0, 1.0, 1.0), (2e-5, 2e-5, 2e-5),
    (1234.0, 1000.0, 2000.0), (0.0049, 0.002, 0.005)])
def test_nice_number_is_1_2_or_5_times_a_power_of_ten(value, down, up):
    assert draw.nice_number(value) == pytest.approx(down, rel=1e-12)
    assert draw.nice_number(value, up=True) == pytest.approx(up, rel=1e-12)


def test_nice_number_takes_other_steps():
    """The Newton view's zooms (1, 2, 3 or 5 times a power of ten) and summary.png's two digits."""
    assert [draw.nice_number(v, (1, 2, 3, 5)) for v in (4.0, 31.0, 7000.0)] == [3.0, 30.0, 5000.0]
    two_digits = [draw.nice_number(v, range(10, 100)) for v in (38.79, 0.5432, 99.99, 1234.0)]
    assert two_digits == [38.0, 0.54, 99.0, 1200.0]


def test_arrow_heads_sit_behind_the_tip_on_either_side():
    tail, head = np.array([[0.0, 0.0], [5.0, 5.0]]), np.array([[10.0, 0.0], [5.0, 5.0]])
    corners = draw.arrow_heads(tail, head, 4.0)
    assert corners.shape == (2, 2, 2)
    assert sorted(corners[0].tolist()) == [[6.0, -2.0], [6.0, 2.0]]
    assert np.array_equal(corners[1], [[5.0, 5.0], [5.0, 5.0]])      # no length: its tip


def test_the_arrows_scale_coarsens_at_the_impact_so_no_arrow_is_longer_than_arrow_fit(monkeypatch):
    """The default run's first 60 steps drawn as frames.FrameWriter draws them (one view): no arrow
    (normal, or friction drawn FRICTION_ZOOM longer) is longer than ARROW_FIT m, 3/4 of the square's
    side (at the impact, steps 31 to 34, they reached 1.39 m at 1 m per weight, through the square);
    the scale is 1 m per weight until an arrow would be longer, then the smallest of 2, 5, 10, ...
    times it that fits, kept from then on; the legend says the scale drawn; and the red ink of the
    normal forces lies within ARROW_FIT m (in pixels) of the contact nodes."""
    pygame = draw.load_pygame()
    drawn = legibility.record_text(monkeypatch)
    scene = simulator.build_scene()
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    per_weight = draw.newton_per_metre(scene)                 # N per m of arrow at factor 1
    weight = float(scene.m.sum() * np.hypot(*scene.g))
    assert per_weight == pytest.approx(weight / draw.ARROW_PER_WEIGHT)
    factors, longest_at_1 = [], []
    for record in simulator.simulate(scene, 60):
        run = frames.frame_run(scene, record.x, record.report, "mu = 0.11", draw.BLUE, True)
        view.follow(diagnostics.centre_of_mass(scene, record.x)[None])
        start = len(drawn)
        surface, top = draw.draw_frame(pygame, [run], record.t, view, fonts, per_weight)
        factor = view.arrow_factor
        friction = draw.FRICTION_ZOOM * np.hypot(*run["friction"].T).max(initial=0.0)
        longest = max(np.hypot(*run["normal"].T).max(initial=0.0), friction) / per_weight   # m, x1
        assert longest / factor <= draw.ARROW_FIT
        assert draw.nice_number(factor) == factor and factor >= max(factors, default=1.0)
        if factor > max(factors, default=1.0):              # raised here: the smallest that fits
            assert longest / draw.nice_number(0.99 * factor) > draw.ARROW_FIT
        words = "the weight M|g|" if factor == 1 else f"{factor:g} x the weight M|g|"
        scale = f"{draw.ARROW_PER_WEIGHT:g} m of arrow = {factor * weight:.5g} N ({words})"
        assert scale in [text for text, _, _ in drawn[start:]]
        factors.append(factor)
        longest_at_1.append(longest)
        pixels = pygame.surfarray.array3d(surface)[:, top:]
        red = np.argwhere(np.all(pixels == draw.NORMAL_COLOR, axis=2)) + [0, top]
        nodes = view(record.x[np.hypot(*run["normal"].T) > 0.0])
        if len(red):
            reach = np.hypot(*(red[:, None, :] - nodes[None, :, :]).T).min(axis=0)   # px to a node
            assert reach.max() <= draw.ARROW_FIT * view.scale + 2
    assert max(longest_at_1) > 1.3 and factors[0] == 1.0 < factors[-1]       # (measured: 1.39, x2)


def test_a_view_maps_world_to_pixels_y_down_and_leaves_its_input():
    """View: (p - centre) x scale from the picture's middle, y flipped (pixels count down); the
    points given are not changed (the pixels are a new array)."""
    view = draw.View(scale=100.0, size=400, height=300)
    view.center = np.array([1.0, 2.0])
    points = np.array([[1.0, 2.0], [2.0, 2.5]])
    assert view(points).tolist() == [[200.0, 150.0], [300.0, 100.0]]
    assert points.tolist() == [[1.0, 2.0], [2.0, 2.5]]
    assert view([1.5, 1.0]).tolist() == [250.0, 250.0]     # one point, as a list


def test_a_chalk_that_presses_nothing_scales_its_arrows_by_its_weight():
    """press 0: no press to scale the arrows by (a zero scale was an OverflowError in nice_number
    as the first frame was drawn): the chalk's weight instead."""
    scene = simulator.build_chalk_scene(press=0.0)
    force, words = draw.reference_force(scene)
    assert words == "the weight M|g|" and force == pytest.approx(float(scene.m.sum()) * 9.81)



@pytest.mark.parametrize("g, words", [(0.0, "M x 9.81 m/s^2"), (1e-320, "M x 9.81 m/s^2"),
                                      (1e-100, "the weight M|g|")])
def test_no_gravity_or_one_too_weak_scales_the_arrows_by_the_weight_at_9_81(g, words, tmp_path):
    """A subnormal gravity (a tester's --gravity 0,-1e-320) made the weight's scale 5e-321 N:
    the impact's force over it passed float64, an OverflowError in nice_number as a frame was
    drawn (a traceback, exit 1). Below WEAKEST_GRAVITY the arrows are scaled by M x 9.81 m/s^2,
    and say so; the run draws its frames and ends as any other."""
    args = ["--gravity", f"0,{-g}", "--center", "0,-0.4", "--v0", "0,-3"]
    scene = simulator.build_scene(gravity=(0.0, -g), center=(0.0, -0.4), v0=(0.0, -3.0))
    weight = float(scene.m.sum()) * (9.81 if words.startswith("M x") else g)
    force, said = draw.reference_force(scene)
    assert said == words and force == pytest.approx(weight)
    code, lines = run_main(*args, "--duration", "0.2", "--out", str(tmp_path))
    assert code == 0 and lines[-1].startswith("wrote "), lines


LINES = """
import hashlib, os, random, sys
sys.path.insert(0, sys.argv[1])
os.environ["SDL_VIDEODRIVER"] = "dummy"
from viewer.pictures import draw
pygame, made, random = draw.load_pygame(), hashlib.md5(), random.Random(1)
surface = pygame.Surface((40, 40))
for _ in range(1000):       # ends on or within float32's reach of a pixel's edge, as a body at rest
    surface.fill((255, 255, 255))
    ends = [[random.randint(5, 30) + random.choice([0.0, 1e-6, -7e-6, 0.5]) for _ in "xy"]
            for _ in "ab"]
    draw.polyline(pygame, surface, (0, 0, 255), ends)
    made.update(pygame.image.tobytes(surface, "RGB"))
print(made.hexdigest())
"""


def test_a_segment_is_drawn_the_same_in_every_process():
    """draw.polyline of two points in 6 fresh processes: the same pixels. Through pygame-ce
    2.5.8's aalines, 1000 such segments drawn twice in 5 processes gave 2 different pictures in 2
    of 5 (summary.png changed a pixel from one run to the next)."""
    import subprocess
    import sys

    from helpers import ROOT
    made = {subprocess.run([sys.executable, "-c", LINES, ROOT], capture_output=True, text=True,
                           check=True).stdout for _ in range(6)}
    assert len(made) == 1


@pytest.mark.parametrize("size", [(849, 474), (1, 1), (3, 7)])
def test_png_data_holds_the_surface_s_pixels_in_24_bits(tmp_path, size):
    """draw.png_data's own PNG (zlib, filter byte 0): pygame loads back the surface's pixels, every
    colour of a random picture, from 24-bit RGB (IHDR colour type 2); the same bytes each time."""
    pygame = draw.load_pygame()
    surface = pygame.Surface(size)
    colours = np.random.default_rng(42).integers(0, 256, (*size, 3))
    pygame.surfarray.blit_array(surface, colours)
    data = draw.png_data(pygame, surface)
    assert data[12:16] == b"IHDR" and data[24:26] == bytes([8, 2])      # 8 bits, r g b
    (tmp_path / "p.png").write_bytes(data)
    loaded = pygame.image.load(str(tmp_path / "p.png"))
    assert loaded.get_size() == size
    assert np.array_equal(pygame.surfarray.array3d(loaded), colours)
    assert draw.png_data(pygame, surface) == data


@pytest.mark.parametrize("height", [30, 300, 652, 900, 1200])
def test_fonts_take_the_least_size_whose_capitals_reach_the_height_s_share(height):
    """draw.fonts searches from CAP_RATIO's guess down and up: its (title, text) fonts are the
    default font at the least size, counted up from 1, whose capitals reach TITLE_SCALE x
    MIN_CAP_HEIGHT and MIN_CAP_HEIGHT of `height` (the same metrics as that size's own font)."""
    pygame = draw.load_pygame()
    cap = draw.MIN_CAP_HEIGHT * height
    chosen = draw.fonts(pygame, height)
    for want, font in zip((draw.TITLE_SCALE * cap, cap), chosen):
        least = next(size for size in itertools.count(1)
                     if draw.cap_height(pygame.font.Font(None, size)) >= want)
        expected = pygame.font.Font(None, least)
        assert ((font.get_height(), font.get_ascent(), font.metrics("Hg"), font.size("0.5 m"))
                == (expected.get_height(), expected.get_ascent(), expected.metrics("Hg"),
                    expected.size("0.5 m")))
