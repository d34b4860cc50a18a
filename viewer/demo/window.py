"""The live window, `python simulator.py --window`: the run as it is computed, paced to wall-clock time,
for an instructor to drive in front of a class, down to one Newton iteration.

Keys: space pauses and resumes; while paused, the right arrow advances one time step and n one Newton
iteration of the current step (the iterate, the direction p at each node, the CCD bound on alpha, the
accepted alpha after halving, ||p||_inf / h against tol: Algorithm 4 happening); r restarts from the
initial state; Esc, q or the window's close button end the run. At the end of the run the window
stays open on the last frame until closed.

Here: the window's loop (the keys, the status lines, drawing), opening the display and the command
line's entry point. What the keys do, the pacing and the files are viewer.demo.live's (no pygame); the
frames are drawn by viewer.pictures.draw, as in the files (the slope's marks, the contact forces; the chalk
zoomed as its frames zoom it, its hand and the marks its tip leaves, live.LiveRun.marks, with their
magnified strip beside the chalk: viewer.pictures.marks); a Newton iterate by viewer.demo.newton_view. Files are
written only when --out is given: then those of a run without the window, by the same code, each
step once.
"""
import contextlib
import math
import os
import sys

import utils
from analysis import diagnostics
from viewer.pictures import draw, frames
from viewer.demo import live, newton_view
from viewer.command import run as orchestration

FPS = 60                  # frames drawn per second at most
MIN_FPS = 20              # ... and at least, when the steps fall behind (the other frames are dropped)
FIT = 0.85                # by default the window's side is this fraction of the display's smaller side,
                          # leaving room for the title bar and desktop panels (652 px on 1024x768)
MIN_SIZE, MAX_SIZE = 300, 16384   # px; 16384 is the largest texture common graphics drivers accept
# SDL's drivers that draw into memory only: it falls back to one of them when it finds no display
MEMORY_DRIVERS = ("dummy", "offscreen")
KEYS = (100, 100, 100)    # the key hints at the bottom (contrast 5.9:1 on white, as draw.BLACK ... are above 4.5)
BOARD_ROW = 0.85          # the chalk's board this far down the window (the frames': 0.75), the status above it


class LiveWindow(live.LiveDemo):
    """The demo loop: read the keys, take the steps that are due (live.LiveDemo), draw, wait for the
    next frame."""

    def __init__(self, pygame, screen, scene, steps, speed=1.0, output=None, clock=None, log=None,
                 label=None, forces=True):
        super().__init__(scene, steps, speed, output, clock, log)    # output: the live.Files written, or None
        self.pygame, self.screen = pygame, screen
        self.size = screen.get_width()
        self.label = label or f"mu = {scene.mu:g}"
        self.newton_per_metre = draw.newton_per_metre(scene) if forces else None
        self.view = draw.View.of(scene, self.size)      # the frames' view at the window's size (the square:
        if scene.hand is not None:                      # the lecture's 4.5 m across; the chalk zoomed as they zoom it)
            self.view.center[1] = (BOARD_ROW - 0.5) * self.size / self.view.scale
        self.fonts = draw.fonts(pygame, self.size)      # the frames' (title, text), at the window's size
        self.font = self.fonts[1]                       # the status lines and the key hints
        self.slow_frames = 0        # frames drawn with the "slower than real time" note
        self.frames = 0
        self.drawn_at = -math.inf   # when the last frame was drawn
        self.inset = None           # the Newton view's Inset, as last drawn
        self.text_bottom = 0        # the first row of pixels below the status lines, as last drawn
        self.reserve = None         # the rows draw.draw_frame kept for the status and the keys, as last drawn

    # -- the loop -------------------------------------------------------------------------------

    def loop(self):
        """Run until Esc, q or the close button; the exit code: 0, or 1 after a failed step or write."""
        self.pacer.start(self.run.t)
        while not self.done:
            started = self.clock.now()
            events = self.pygame.event.get()
            for event in events:
                self.handle(event)
            playing = self.playing and not self.done
            if playing:
                self.play()
            if events or self.frames == 0 or (playing and self.frame_due()):   # else nothing changed
                self.draw()
            self.clock.sleep(max(0.0, started + 1.0 / FPS - self.clock.now()))
        return 0 if self.failure is None and self.write_error is None else 1

    def handle(self, event):
        pg = self.pygame
        if event.type == pg.QUIT or (event.type == pg.KEYDOWN and event.key in (pg.K_ESCAPE, pg.K_q)):
            self.done = True
        elif event.type == pg.KEYDOWN:
            self.message = None
            if event.key == pg.K_SPACE:
                self.toggle_pause()
            elif event.key == pg.K_r:
                self.restart()
            elif event.key == pg.K_RIGHT and not self.playing:
                self.one_step()
            elif event.key == pg.K_n and not self.playing:
                self.one_newton_iteration()

    def frame_due(self):
        """Draw after this play? Yes while the steps keep up (FPS a second at most); when they are
        behind, only every 1/MIN_FPS s: the time goes to the steps (frames dropped, not simulated time)."""
        behind = self.pacer.due() - self.run.t >= self.scene.h
        return not behind or self.stopped() or self.clock.now() - self.drawn_at >= 1.0 / MIN_FPS

    # -- drawing --------------------------------------------------------------------------------

    def draw(self):
        """The frame a run without the window writes (viewer.pictures.draw: the slope with its marks, the
        square, the contact forces; the chalk's board, hand and tip's marks), or the Newton iterate in
        progress instead of the forces; the window's status under the title and legend (ending at
        self.text_bottom), the keys at the bottom, the chalk's marks' strip (viewer.pictures.marks) off both;
        within a Newton step, its inset (self.inset) in the room between them instead."""
        run, pg = self.run, self.pygame
        x = run.shown_x
        self.view.follow(diagnostics.centre_of_mass(self.scene, x)[None])     # as the frames follow it
        forces = self.newton_per_metre is not None and run.iterate is None
        runs = [frames.frame_run(self.scene, x, run.report, self.label, draw.BLUE, forces)]
        runs[0]["marks"] = run.marks if self.scene.hand is not None else None      # as frames.FrameWriter
        line, width = self.font.get_linesize(), self.size - 24
        rows = [(row, color) for text, color in self.status_lines()
                for row in self.rows(text, width)]
        bottom = [row for text in self.help_lines() for row in self.rows(text, width)]
        # the chalk's marks' strip off the status lines and the key hints (and none beside the Newton view's inset)
        self.reserve = (len(rows) * line, 6 + len(bottom) * line) if run.iterate is None else None
        surface, top = draw.draw_frame(pg, runs, run.t, self.view, self.fonts,
                                       self.newton_per_metre if forces else None, self.reserve)
        if run.iterate is not None:
            newton_view.draw_iterate(pg, surface, self.scene, run.iterate, self.view)
        for row, (text, color) in enumerate(rows):
            surface.blit(self.font.render(text, True, color), (12, top + row * line))
        for row, text in enumerate(reversed(bottom), start=1):
            surface.blit(self.font.render(text, True, KEYS), (12, self.size - 6 - row * line))
        self.inset, self.text_bottom = None, top + len(rows) * line
        if run.iterate is not None:
            self.inset = newton_view.place_inset(pg, surface, self.scene, run.iterate, self.view, self.fonts,
                                                 self.text_bottom + 8, self.size - 6 - len(bottom) * line - 8)
        self.screen.blit(surface, (0, 0))
        pg.display.flip()
        self.frames += 1
        self.slow_frames += self.slow is not None
        self.drawn_at = self.clock.now()

    def rows(self, text, width):
        """A line of the status or the key hints in rows within `width` px, broken between its
        phrases (newton_view.phrase_rows: "CCD bound ... = 0.7115" over "(black ring: ...)")."""
        return newton_view.phrase_rows(self.font, text, width)

    def status_lines(self):
        """(text, colour) under the caption: what the window is doing, the Newton iterate's figures."""
        run, lines = self.run, []
        if self.failure is not None:
            lines.append((f"step failed: {self.failure}", draw.RED))
        elif run.finished:
            lines.append((f"end of the run ({run.steps} steps)", draw.BLACK))
        elif self.playing:
            lines.append((f"playing at {self.speed:g}x real time", draw.BLACK))
            if self.slow is not None:
                lines.append((f"slower than real time: {self.slow * self.speed:.2g}x (asked {self.speed:g}x)", draw.RED))
        else:
            lines.append((f"paused {'in' if run.iterate is not None else 'before'} step {run.index + 1}", draw.BLACK))
        if self.write_error is not None:
            lines.append((f"files stopped: {self.write_error.strerror or self.write_error}", draw.RED))
        if self.message:
            lines.append((self.message, draw.GREEN))
        lines += [(f"warning: {text}", draw.RED) for kind, text in self.warnings.items() if kind != "slow"]
        if self.scene.hand is not None and run.iterate is None:    # the chalk's figures of the state x^n
            lines += [(text, draw.BLACK) for text in live.tip_lines(self.scene, run.x, run.v, run.t)]
        if run.iterate is not None:
            lines += [(text, draw.BLACK) for text in newton_view.iterate_lines(run, self.scene)]
        return lines

    def help_lines(self):
        if self.stopped():
            return ["r: restart   q, Esc: quit"]
        if self.playing:
            return ["space: pause   r: restart   q, Esc: quit"]
        return ["space: play   right arrow: one step   n: one Newton iteration   r: restart   q, Esc: quit"]


# ------------------------------------------------------------------------------------------------
# Opening the display, and the command line's entry point
# ------------------------------------------------------------------------------------------------

def display_problem(driver, requested):
    """Why a window on SDL video driver `driver` would show nothing, or None. SDL falls back to a driver
    that draws into memory when it finds no display; that is fine only when asked for by name
    (SDL_VIDEODRIVER=dummy, as the tests and benchmarks run)."""
    if driver in MEMORY_DRIVERS and driver != requested:
        where = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
        found = f"none at DISPLAY={where}" if where else "DISPLAY is not set"
        return (f"no display to open the window on ({found}; SDL fell back to its {driver!r} driver): "
                f"run on a desktop, under Xvfb, or without --window")
    return None


@contextlib.contextmanager
def c_stderr_hidden():
    """SDL's C code writes its probes' complaints ("XDG_RUNTIME_DIR is invalid") straight to file
    descriptor 2; hide them while the display opens, so a failure reads as one line."""
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def open_display():
    """pygame with its display initialized on a real screen; ValueError when there is none."""
    requested = os.environ.get("SDL_VIDEODRIVER")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    os.environ.setdefault("SDL_VIDEO_CENTERED", "1")
    import pygame
    try:
        with c_stderr_hidden():
            pygame.display.init()
    except pygame.error as err:
        raise ValueError(f"no display to open the window on (SDL: {err}): run on a desktop, under Xvfb, "
                         f"or without --window") from None
    problem = display_problem(pygame.display.get_driver(), requested)
    if problem:
        pygame.display.quit()
        raise ValueError(problem)
    pygame.font.init()
    return pygame


def window_size(size, pygame):
    """--size (checked by run_window), or the largest square that fits the display: FIT of its smaller side."""
    if size is not None:
        return int(size)
    info = pygame.display.Info()
    if info.current_w > 0 and info.current_h > 0:
        return max(MIN_SIZE, int(FIT * min(info.current_w, info.current_h)))
    return draw.RESOLUTION


def check_size(value):
    """--size as a whole number of pixels in [MIN_SIZE, MAX_SIZE]; ValueError otherwise."""
    if not (math.isfinite(value) and float(value).is_integer() and MIN_SIZE <= value <= MAX_SIZE):
        raise utils.ParameterError("size", f"size must be a whole number of pixels in [{MIN_SIZE}, {MAX_SIZE}] "
                                           f"(the window's side), got {value:g}")
    return int(value)


def check_speed(value):
    """--speed (default 1): simulated seconds per wall-clock second, finite and > 0; ValueError otherwise."""
    if value is None:
        return 1.0
    if not (math.isfinite(value) and value > 0.0):
        raise utils.ParameterError("speed", f"speed must be a finite number > 0 (simulated seconds per second), "
                                            f"got {value:g}")
    return value


def run_window(plan, speed, size, signals, clock=None, log=None):
    """`python simulator.py --window`: check the flags, open the window, run the demo until closed;
    with --out (plan.out), write what a run without the window writes, as it does. Returns the exit
    code: 0; 1 after a failed step or write; 130 after Ctrl+C; 143 after SIGTERM."""
    speed, log = check_speed(speed), log or sys.stderr
    if size is not None:
        check_size(size)
    with signals.held():                        # SDL starts after the run's signal handlers: they stay ours
        pygame = open_display()                 # before anything is written
    try:
        return _demo(pygame, plan, speed, size, signals, clock or live.WallClock(), log)
    finally:
        pygame.display.quit()


def _demo(pygame, plan, speed, size, signals, clock, log):
    """The window on the display, with the files when --out is given, until it is closed; the run ends
    as a run without the window does (viewer.command.run.end)."""
    scene = plan.scenes[0]
    folder = plan.folder(signals) if plan.out is not None else None
    output, window, failure = None, None, None
    try:
        orchestration.warn(plan, log)
        screen = pygame.display.set_mode((window_size(size, pygame),) * 2)
        pygame.display.set_caption(f"simulator.py: mu = {scene.mu:g}, " + (f"n_seg = {scene.params['n_seg']}" if scene.hand is None
                                   else f"chalk, grip {scene.hand.k_hand:g} N/m"))
        if folder is not None:
            output = live.Files(plan, folder, log)
        window = LiveWindow(pygame, screen, scene, plan.steps[0], speed, output, clock, log, plan.labels[0],
                            plan.forces)
        window.loop()
        failure = window.write_error or window.failure
        failure = failure and orchestration.failure_of(failure, plan)
    except orchestration.ENDINGS as err:         # Ctrl+C, SIGTERM; starting the files (frame 0)
        failure = orchestration.failure_of(err, plan)
    steps = window.run.index if window else 0
    written = f"; {orchestration.written(plan)} in {orchestration.where(plan, folder)}" if output else ""
    done = f"simulator.py: {steps} steps ({steps * scene.h:.2f} s) in the window{written}"
    return orchestration.end(plan, signals, folder, [output.track] if output else [], output and output.frame_log,
                             failure, log, done)
