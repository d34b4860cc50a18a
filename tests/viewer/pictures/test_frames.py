"""viewer/pictures/frames.py: when each frame is due. Frames come every `stride` steps of the
smallest h, numbered from 0, the last at the end of the longest run; each run is shown at the last
step it has reached by then."""
import struct
import types
import zlib

import numpy as np
import pytest

import simulator
from helpers.command import run_main
from viewer.pictures import draw, frames


def tracks(*runs):
    """Stand-ins for recording.Track: (h, steps) each."""
    return [types.SimpleNamespace(scene=types.SimpleNamespace(h=h), steps=steps)
            for h, steps in runs]


def test_frames_every_stride_steps_and_the_last_state():
    runs = tracks((0.01, 10))
    assert list(frames.frame_steps(runs, 4)) == [(0, [0]), (1, [4]), (2, [8]), (3, [10])]
    assert frames.frame_count([r.scene for r in runs], [10], 4) == 4
    assert [j for j, _ in frames.frame_steps(tracks((0.01, 12)), 4)] == [0, 1, 2, 3]   # 12: a frame


@pytest.mark.parametrize("runs, stride, expected", [
    (((0.01, 30), (0.02, 15)), 5, [[0, 0], [5, 2], [10, 5], [15, 7], [20, 10], [25, 12], [30, 15]]),
    (((0.01, 20), (0.03, 4)), 10, [[0, 0], [10, 3], [20, 6]])])
def test_a_comparison_of_time_steps_shows_each_run_at_the_same_times(runs, stride, expected):
    """Frame j at t = j stride h_min: a run of larger h at its last step by then (floor); a run that
    ended earlier is asked for steps past its end, and Track.advance stops at its last."""
    runs = tracks(*runs)
    got = [targets for _, targets in frames.frame_steps(runs, stride)]
    count = frames.frame_count([r.scene for r in runs], [r.steps for r in runs], stride)
    assert got == expected and len(got) == count


def test_the_frames_friction_arrows_are_the_steps_own_force():
    """What a frame draws as friction is the step's report.friction_force itself (the force
    log.csv's W_friction sums), not one computed again: here under Algorithm 5, where it differs
    from lagged."""
    scene = simulator.build_scene(friction_updates=5)
    for record in simulator.simulate(scene, 40):
        pass
    run = frames.frame_run(scene, record.x, record.report, "run", (0, 0, 0), forces=True)
    drawn = run["friction"]
    assert drawn is record.report.friction_force and np.abs(drawn).max() > 0.0


@pytest.mark.parametrize("runs, stride", [
    (((1e-12, 3),), 33_333_333_333),        # --h 1e-12 --steps 3: the default stride, 1 / (30 h)
    (((0.01, 30),), 10 ** 11),              # --frame-stride 1e11 --steps 30
    (((1e-160, 30),), 3 * 10 ** 157)])      # the tablecloth's --h 1e-160 --steps 30
def test_a_stride_longer_than_the_run_still_takes_every_step(runs, stride):
    """A stride far beyond the run: frame 0 and a last frame at the run's last step, so the run
    takes every step it counts (it took none where frame_count rounded the tiny ratio to 0)."""
    runs = tracks(*runs)
    assert list(frames.frame_steps(runs, stride)) == [(0, [0]), (1, [runs[0].steps])]


def test_frames_are_the_same_bytes_run_to_run(tmp_path):
    """Two runs of the same command write the same frames and OBJs, byte for byte."""
    for out in ("a", "b"):
        code, _ = run_main("--steps", "30", "--out", str(tmp_path / out))
        assert code == 0
    names = sorted(p.name for p in (tmp_path / "a").glob("frame_*"))
    assert len(names) == 2 * 11        # 30 steps, a frame every 3rd: a PNG and an OBJ each
    assert names == sorted(p.name for p in (tmp_path / "b").glob("frame_*"))
    for name in names:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name


def palette_rows(pygame, surface):
    """The rows a PNG of `surface`'s PALETTE indices holds, made whole at once: each row's filter
    byte 0, then the indices of its pixels (draw.palette_indices)."""
    width, height = surface.get_size()
    rows, scratch = np.zeros((height, 1 + width), np.uint8), np.empty((2, height, width), np.uint32)
    pixel = np.array(pygame.surfarray.pixels2d(surface).T)     # a copy: the surface unlocked
    draw.palette_indices(pixel, surface.get_shifts(), rows[:, 1:], scratch)
    return rows.tobytes()


def idat_rows(png):
    """The decompressed rows of a PNG's IDAT chunks (their CRCs checked)."""
    at, stream = 8, b""
    while at < len(png):
        (length,), kind = struct.unpack(">I", png[at:at + 4]), png[at + 4:at + 8]
        assert struct.unpack(">I", png[at + 8 + length:at + 12 + length])[0] == zlib.crc32(
            png[at + 4:at + 8 + length])
        stream += png[at + 8:at + 8 + length] if kind == b"IDAT" else b""
        at += 12 + length
    return zlib.decompress(stream)


def test_a_kept_surface_and_bands_carry_nothing_over():
    """Frames drawn over the writer's surface and encoded by one BandedPng, which keeps the bands
    that did not change, are the bytes a new surface and a new BandedPng give, and their rows are
    the palette indices of the whole picture made at once."""
    pygame = draw.load_pygame()
    scene = simulator.build_scene()
    view, fonts = draw.View.of(scene), draw.fonts(pygame)
    states = [record.x for record in simulator.simulate(scene, 60)][::29]
    pictures = [dict(frames.frame_run(scene, x, None, "run", draw.BLUE, False), marks=None)
                for x in states]
    surface, png = pygame.Surface((view.size, view.size)), frames.BandedPng(view.size, view.size)
    kept, pieces = [], []
    for p, t in zip(pictures, (0.0, 0.3, 0.6)):
        kept.append(png.data(pygame, draw.draw_frame(pygame, [p], t, view, fonts,
                                                     surface=surface)[0]))
        pieces.append(list(png.pieces))
    new = [draw.draw_frame(pygame, [p], t, view, fonts)[0]
           for p, t in zip(pictures, (0.0, 0.3, 0.6))]
    assert kept == [frames.BandedPng(view.size, view.size).data(pygame, s) for s in new]
    assert [idat_rows(b) for b in kept] == [palette_rows(pygame, s) for s in new]
    assert len(set(kept)) == 3
    kept_pieces = [a is b for a, b in zip(pieces[1], pieces[2])]
    assert any(kept_pieces) and not all(kept_pieces)        # some bands kept, some new
    assert png.data(pygame, surface) == kept[2]             # the same picture again: all kept
    assert all(a is b for a, b in zip(pieces[2], png.pieces))


def test_a_picture_of_bands_not_whole_decodes_and_loads(tmp_path):
    """A picture whose height is no multiple of BAND, all black (the pixels a new BandedPng's
    record of the last frame holds): every band written, and pygame loads the PNG."""
    pygame = draw.load_pygame()
    surface = pygame.Surface((7, 2 * frames.BAND + 3))
    surface.fill(draw.BLACK)
    png = frames.BandedPng(*surface.get_size()).data(pygame, surface)
    assert idat_rows(png) == palette_rows(pygame, surface)
    (tmp_path / "f.png").write_bytes(png)
    back = pygame.image.load(str(tmp_path / "f.png"))
    assert back.get_size() == surface.get_size() and back.get_at((6, 34))[:3] == draw.BLACK


def test_adler32_of_joined_bytes():
    """adler32_joined(adler32(X), adler32(Y), len(Y)) is adler32(X + Y)."""
    rng = np.random.default_rng(7)
    for n, m in [(0, 0), (0, 5), (3, 0), (100, 70_000), (70_000, 100), (5_000, 1_000_000)]:
        x, y = rng.integers(0, 256, n, np.uint8).tobytes(), b"\xff" * m
        assert frames.adler32_joined(zlib.adler32(x), zlib.adler32(y), m) == zlib.adler32(x + y)
