"""The live window, `python simulator.py --window` (docs/live-demo.md): its loop, its display."""
import contextlib
import copy
import math
import os
import sys

import numpy as np

import utils
from analysis import closing, diagnostics
from viewer.pictures import draw, frames, wrap
from viewer.demo import live, newton_view
from viewer.command import run as orchestration

FPS = 60                  # frames drawn per second at most,
MIN_FPS = 20              # ... and at least while the steps are behind (the others dropped)
FIT = 0.85                # the default side, of the display's smaller one (652 px on 1024x768)
MIN_SIZE, MAX_SIZE = 300, 16384     # px; 16384: the largest texture common drivers accept
MEMORY_DRIVERS = ("dummy", "offscreen")     # SDL's drivers that draw into memory only
KEYS = (100, 100, 100)    # the key hints' grey: contrast 5.9:1 on white
BOARD_ROW = 0.85          # the chalk's board this far down the window (the frames': 0.75)


class LiveWindow(live.LiveDemo):
    """The demo's loop: read the keys, take the steps due (live.LiveDemo), draw, wait a frame."""

    def __init__(self, pygame, screen, scene, steps, speed=1.0, output=None, clock=None, log=None,
                 label=None, forces=True):
        super().__init__(scene, steps, speed, output, clock, log)
        self.pygame, self.screen, self.size = pygame, screen, screen.get_width()
        self.label = label or f"mu = {scene.mu:g}"
        self.newton_per_metre = draw.newton_per_metre(scene) if forces else None
        self.view = self.new_view()
        self.fonts = draw.fonts(pygame, self.size)      # (title, text): the frames', resized
        self.font = self.fonts[1]
        # frames drawn, those with "slower than real time", when the last was
        self.frames, self.slow_frames, self.drawn_at = 0, 0, -math.inf
        # as last drawn: the Newton inset, the first row under the status, draw_frame's reserve
        self.inset, self.text_bottom, self.reserve = None, 0, None
        self.shown, self.tops = self.view, {}   # the view drawn (clear_of_text); legends' bottoms

    def new_view(self):
        """The frames' view at the window's size (the chalk's board at BOARD_ROW), as a run starts:
        its arrow scale and its zoom afresh."""
        view = draw.View.of(self.scene, self.size)
        if self.scene.hand is not None:
            view.center[1] = (BOARD_ROW - 0.5) * self.size / view.scale
        return view

    def restart(self):
        """live.LiveDemo.restart, and the view as a new run's."""
        super().restart()
        self.view = self.new_view()

    def loop(self, check=None):
        """Run until Esc, q or the close button: 0, or 1 after a failed step or write; `check()`
        (a run's Signals.check) once a frame."""
        self.pacer.start(self.run.t)
        while not self.done:
            if check is not None:
                check()
            started = self.clock.now()
            events = self.pygame.event.get()
            for event in events:
                self.handle(event)
            playing = self.playing and not self.done
            if playing:
                self.play()
            # behind: the time goes to the steps, a frame drawn every 1/MIN_FPS s (the rest dropped)
            behind = self.pacer.due() - self.run.t >= self.scene.h and not self.stopped()
            due = not behind or self.clock.now() - self.drawn_at >= 1.0 / MIN_FPS
            if events or self.frames == 0 or (playing and due):
                self.draw()
            self.clock.sleep(max(0.0, started + 1.0 / FPS - self.clock.now()))
        return 0 if self.failure is None and self.write_error is None else 1

    def handle(self, event):
        pg = self.pygame
        keys = {pg.K_SPACE: self.toggle_pause, pg.K_r: self.restart}
        if not self.playing:
            keys |= {pg.K_RIGHT: self.one_step, pg.K_n: self.one_newton_iteration}
        if event.type == pg.QUIT:
            self.done = True
        elif event.type == pg.KEYDOWN:
            self.done |= event.key in (pg.K_ESCAPE, pg.K_q)
            self.message = None
            keys.get(event.key, lambda: None)()

    def draw(self):
        """The frame (or Newton iterate), the status under it, the key hints, the strip or inset."""
        run, pg, it = self.run, self.pygame, self.run.iterate
        self.view.follow(diagnostics.centre_of_mass(self.scene, run.shown_x)[None])
        forces = self.newton_per_metre if it is None else None
        picture = frames.frame_run(self.scene, run.shown_x, run.report, self.label, draw.BLUE,
                                   forces is not None)
        picture["marks"] = run.marks
        line, width = self.font.get_linesize(), self.size - 24
        rows = [(row, color) for text, color in self.status_lines()
                for row in wrap.phrase_rows(self.font, text, width)]
        hints = [row for text in self.help_lines()
                 for row in wrap.phrase_rows(self.font, text, width)]
        self.reserve = (len(rows) * line, 6 + len(hints) * line) if it is None else None
        hints_top, kind = self.size - 6 - len(hints) * line, forces is None
        if kind not in self.tops:       # the legends' bottom, learnt once for each kind of frame
            self.tops[kind] = draw.draw_frame(pg, [picture], run.t, self.view, self.fonts,
                                              forces)[1]
        shown = clear_of_text(self.view, self.drawn_points(), self.tops[kind] + len(rows) * line,
                              hints_top - 2 * line, line // 2)
        surface, top = draw.draw_frame(pg, [picture], run.t, shown, self.fonts, forces,
                                       self.reserve)
        self.view.arrow_factor, self.tops[kind] = shown.arrow_factor, top
        self.shown = shown
        if it is not None:
            newton_view.draw_iterate(pg, surface, self.scene, it, shown)
        for row, (text, color) in enumerate(rows):
            surface.blit(self.font.render(text, True, color), (12, top + row * line))
        for row, text in enumerate(reversed(hints), start=1):
            surface.blit(self.font.render(text, True, KEYS), (12, self.size - 6 - row * line))
        self.text_bottom = top + len(rows) * line
        self.inset = None if it is None else newton_view.place_inset(
            pg, surface, self.scene, it, shown, self.fonts, self.text_bottom + 8, hints_top - 8)
        self.screen.blit(surface, (0, 0))
        pg.display.flip()
        self.frames += 1
        self.slow_frames += self.slow is not None
        self.drawn_at = self.clock.now()

    def drawn_points(self):
        """What the picture draws of the run (m): the nodes (x^i too in the Newton view), the
        hand's targets, the pads' corners."""
        scene, run = self.scene, self.run
        points = [run.shown_x] + ([run.iterate.x] if run.iterate is not None else [])
        if scene.hand is not None:
            points.append(scene.hand.targets(run.t))
        if scene.pushed is not None:
            points += scene.pushed.pads(run.shown_x, draw.PAD_DEPTH * self.view.unit)
        return np.concatenate(points)

    def status_lines(self):
        """(text, colour) under the caption: what the window is doing, the figures of the state."""
        run, speed, lines = self.run, self.speed, []
        if self.failure is not None:
            lines.append((f"step failed: {self.failure}", draw.RED))
        elif run.finished:          # and what the closing says the run showed
            lines.append((f"end of the run ({run.steps} steps)", draw.BLACK))
            lines += [(self.result, draw.BLACK)] if self.result else []
        elif self.playing:
            lines.append((f"playing at {speed:g}x real time", draw.BLACK))
            if self.slow is not None:
                rate = f"{self.slow * speed:.2g}x (asked {speed:g}x)"
                lines.append((f"slower than real time: {rate}", draw.RED))
        else:
            where = "in" if run.iterate is not None else "before"
            lines.append((f"paused {where} step {run.index + 1}", draw.BLACK))
        if self.write_error is not None:
            error = self.write_error.strerror or self.write_error
            lines.append((f"files stopped: {error}", draw.RED))
        if self.message:
            lines.append((self.message, draw.GREEN))
        lines += [(f"warning: {text}", draw.RED) for kind, text in self.warnings.items()
                  if kind != "slow"]
        return lines + [(text, draw.BLACK) for text in self.figure_lines()]

    def figure_lines(self):
        """The state's figures: Algorithm 4's in the Newton view, the chalk's tip, the square's
        creep once it sticks (closing.state_words; at the end the result's creep stands alone)."""
        run, scene = self.run, self.scene
        if run.iterate is not None:
            return newton_view.iterate_lines(run, scene)
        if scene.hand is not None:
            return live.tip_lines(scene, run.x, run.v, run.t)
        if scene.surface is not None or (run.finished and self.result):
            return []
        stuck = closing.state_words(scene, run.x, run.v, run.t)
        return [stuck] if stuck else []

    def help_lines(self):
        keys = ("" if self.stopped() else "space: pause   " if self.playing else
                "space: play   right arrow: one step   n: one Newton iteration   ")
        return [keys + "r: restart   q, Esc: quit"]


def clear_of_text(view, points, text_bottom, floor, gap):
    """`view`, or a copy drawing `points` (k, 2; m) from row text_bottom + gap down (px): panned
    down as far as their lowest stays above `floor`, then zoomed out about their lowest. Points
    above the window (a grasp's fingers lifted away from the dropped block) are not drawn."""
    points = points[view(points)[:, 1] >= 0]
    if not len(points):
        return view
    rows = view(points)[:, 1]
    need = text_bottom + gap - rows.min()
    if need <= 0:
        return view
    shown = copy.copy(view)
    pan = min(need, max(0.0, floor - rows.max()))
    shown.center = view.center + [0.0, pan / view.scale]
    low, high = points[np.argmax(rows)], points[np.argmin(rows)]
    q = shown(low)
    room = q[1] - text_bottom - gap
    if pan < need and room > 0 and high[1] > low[1]:    # keep `low` where it is drawn
        shown.scale = room / (high[1] - low[1])
        shown.center = low + [(view.size / 2 - q[0]) / shown.scale,
                              (q[1] - view.height / 2) / shown.scale]
    return shown


def display_problem(driver, requested):
    """Why SDL's `driver` shows nothing (it falls back to a memory driver), unless `requested`."""
    if driver in MEMORY_DRIVERS and driver != requested:
        where = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
        return f"{'none at DISPLAY=' + where if where else 'DISPLAY unset'}; SDL: {driver}"
    return None


def open_display():
    """pygame with its display initialized on a real screen; ValueError when there is none."""
    requested = os.environ.get("SDL_VIDEODRIVER")
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    os.environ.setdefault("SDL_VIDEO_CENTERED", "1")
    import pygame
    sys.stderr.flush()
    saved = os.dup(2)           # what SDL's C code writes to fd 2 is hidden: a failure is one line
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        pygame.display.init()
        problem = display_problem(pygame.display.get_driver(), requested)
    except pygame.error as err:
        problem = f"SDL: {err}"
    finally:
        os.dup2(saved, 2)
        os.close(saved)
    if problem:
        pygame.display.quit()
        raise ValueError(f"--window: no display ({problem}); use a desktop or Xvfb")
    pygame.font.init()
    return pygame


def window_size(size, pygame):
    """--size, or the largest square that fits the display: FIT of its smaller side."""
    info = pygame.display.Info()
    if size is None and min(info.current_w, info.current_h) > 0:
        return max(MIN_SIZE, int(FIT * min(info.current_w, info.current_h)))
    return draw.RESOLUTION if size is None else int(size)


def close_files(window, output):
    """The frames still on their way written (live.Files.close); an error there is the window's
    write error, said as one during the run is, unless the files had stopped already."""
    try:
        output.close()
    except OSError as err:
        if window.write_error is None:
            window.write_error = err
            print(live.files_stopped(output.track.logged, err), file=window.log)


def run_window(plan, speed, size, signals, clock=None, log=None):
    """`python simulator.py --window` (ParameterError: a bad --speed, --size): the demo until
    closed, with --out its files, ended as command.run.end ends a run; exit code 0, 1 (a failed
    step or write), 130, 143."""
    speed = 1.0 if speed is None else utils.check_positive("speed", speed)
    if size is not None and utils.check_whole("size", size, MIN_SIZE) > MAX_SIZE:
        raise utils.ParameterError("size", f"size must be at most {MAX_SIZE} px, got {size:g}")
    log, scene = log or sys.stderr, plan.scenes[0]
    with signals.held():                        # SDL starts after the run's signal handlers
        pygame = open_display()                 # before anything is written
    try:
        folder = plan.folder(signals) if plan.out is not None else None
        output, window, failure = None, None, None
        try:
            orchestration.warn(plan, log)
            screen = pygame.display.set_mode((window_size(size, pygame),) * 2)
            pygame.display.set_caption(f"simulator.py: {plan.labels[0]}")
            output = live.Files(plan, folder, log) if folder is not None else None
            try:
                window = LiveWindow(pygame, screen, scene, plan.steps[0], speed, output, clock,
                                    log, plan.labels[0], plan.forces)
                window.loop(signals.check)
            except BaseException:
                if output is not None:
                    with contextlib.suppress(OSError):      # the window says what ended it
                        output.close()
                raise
            if output is not None:
                close_files(window, output)
            failure = window.write_error or window.failure
            failure = failure and orchestration.failure_of(failure, plan)
        except orchestration.ENDINGS as err:     # Ctrl+C, SIGTERM; starting the files (frame 0)
            failure = orchestration.failure_of(err, plan)
        shown = window.run.index if window else 0
        done = f"simulator.py: the window ended at step {shown} ({shown * scene.h:.2f} s)"
        if output:                      # its log goes to the farthest step: r recomputes the same
            wrote = orchestration.written(plan, folder, [output.track])
            done += (f"; wrote {wrote} (log.csv to step {output.track.logged})"
                     f"{orchestration.where(plan, folder)}")
        return orchestration.end(plan, signals, folder, [output.track] if output else [],
                                 output and output.frame_log, failure, log, done)
    finally:
        pygame.display.quit()
