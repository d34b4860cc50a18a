"""A run's frames drawn, encoded and written by a second process while this one steps on: the
frames of frames.FrameWriter, the same bytes, off the stepping process's core (docs/output.md,
"The frames' process"). A frame counts, in the folder's `written` and the page's frame_log, once
the process says it is written; a full disk or the process's end stop the run as a frame written
here would. The process is in a session (a process group) of its own: the terminal's Ctrl+C and
hangup reach the run alone, which says how it ended."""
import contextlib
import errno
import os
import pickle
import subprocess
import sys
from collections import deque

from viewer.output import files, whole_files
from viewer.pictures import frames

AHEAD = 4       # frames sent and not yet written, at most: the run waits for the process beyond
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SERVE = ("import sys; sys.path.insert(0, sys.argv[1]); "
         "from viewer.command.frame_process import serve; serve()")
ALONE = ({"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP} if sys.platform == "win32"
         else {"start_new_session": True})      # no Ctrl+C (Windows), no terminal (POSIX)


def frame_writer(tracks, folder, forces, frame_log):
    """A FrameProcess; where no process can be started, a frames.FrameWriter (this process)."""
    try:
        return FrameProcess(tracks, folder, forces, frame_log)
    except OSError:
        return frames.FrameWriter(tracks, folder, forces, frame_log)


class FrameProcess:
    """FrameWriter's write(j) and close(), the frames painted and written by `serve` in a process
    of its own, this Python started afresh (the same on every system). Messages are pickles: the
    folder, scenes, tags and forces, then a Frame each, None at the end; it answers each frame
    with None, written, or the (errno, strerror, path) of the OSError that stopped it."""

    def __init__(self, tracks, folder, forces, frame_log):
        self.tracks, self.folder, self.forces, self.frame_log = tracks, folder, forces, frame_log
        self.tags = [tr.tag for tr in tracks]
        self.sent = deque()         # (frame, FrameInfo) of each frame sent and not yet written
        self.process = subprocess.Popen([sys.executable, "-c", SERVE, ROOT], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, **ALONE)
        self.send((folder.folder, [tr.scene for tr in tracks], self.tags, forces), None)

    def send(self, message, frame):
        """`message` sent whole (signals wait); an OSError where the process has ended."""
        with self.folder.signals.held():
            try:
                pickle.dump(message, self.process.stdin)
                self.process.stdin.flush()
            except OSError:                     # its end of the pipe is closed
                raise self.ended(frame) from None

    def write(self, j):
        """Frame j sent to the process; past AHEAD frames, the oldest waited for and counted."""
        frame = frames.frame_of(self.tracks, j, self.forces)
        with self.folder.signals.held():        # sent, and noted as sent: both or neither
            self.send(frame, frame)
            self.sent.append((frame, frames.info_of(self.tracks, frame)))
        while len(self.sent) > AHEAD:
            self.receive()

    def receive(self):
        """The process's word on the oldest frame sent: written (counted), or an OSError. Signals
        wait for it (a few ms, as for a frame written here): an answer read is a frame counted."""
        frame, info = self.sent[0]
        with self.folder.signals.held():
            try:
                said = pickle.load(self.process.stdout)
            except (EOFError, OSError, pickle.UnpicklingError):     # it ended, or broke its word
                self.sent.clear()
                raise self.ended(frame) from None
            if said is not None:
                self.sent.clear()
                raise OSError(*said)
            self.sent.popleft()
            self.folder.written.update(frames.frame_files(frame.index, self.tags))
            self.frame_log.append(info)

    def ended(self, frame):
        """The OSError of the process's end before it wrote `frame`."""
        name = files.frame_png(0 if frame is None else frame.index)
        why = f"the frames' process ended (exit code {self.process.wait()})"
        return OSError(errno.EPIPE, why, self.folder.path(name))

    def close(self):
        """Every frame sent written and counted (or its error raised), the process ended;
        signals wait meanwhile."""
        with self.folder.signals.held():
            try:
                with contextlib.suppress(OSError):      # it ended already
                    pickle.dump(None, self.process.stdin)
                    self.process.stdin.close()
                while self.sent:
                    self.receive()
            finally:
                with contextlib.suppress(OSError):
                    self.process.stdin.close()
                self.process.stdout.close()
                self.process.wait()


def serve():
    """The frames' process: each Frame from stdin painted and its files written whole into the
    folder; its answers on stdout, which nothing else writes to (print goes to stderr)."""
    answers, read = os.fdopen(os.dup(1), "wb"), sys.stdin.buffer
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    try:
        with contextlib.suppress(EOFError, OSError):        # the run ended: nothing to answer
            folder, scenes, tags, forces = pickle.load(read)
            painter = frames.Painter(scenes, tags, forces)
            while (frame := pickle.load(read)) is not None:
                try:
                    for name, data in painter.paint(frame):
                        whole_files.write_whole(os.path.join(folder, name), data)
                except OSError as err:
                    pickle.dump((err.errno, err.strerror, err.filename), answers)
                    answers.flush()
                    return
                pickle.dump(None, answers)
                answers.flush()
    finally:
        with contextlib.suppress(OSError):      # an answer the run no longer reads: dropped
            answers.close()
