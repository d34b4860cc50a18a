"""The output folder: the names of the files a run writes, and removing those of an earlier run.

A run first removes every file whose name is one this program writes (frames, OBJs, CSV logs,
plots.png, summary.png, index.html, and the temporary files of an interrupted atomic write), so a
shorter run never leaves an earlier run's frames beside its own; anything else in the folder is kept.
"""
import os
import re

WRITTEN = re.compile(r"^(frame_\d{5,}(_[\w.=+-]+)?\.(png|obj)|log(_[\w.=+-]+)?\.csv|plots\.png|summary\.png|"
                     r"index\.html|\.tmp-.*)$")


def frame_png(index):
    return f"frame_{index:05d}.png"


def frame_obj(index, tag=""):
    """frame_00012.obj, or frame_00012_mu0.2.obj for one run of a comparison."""
    return f"frame_{index:05d}{'_' + tag if tag else ''}.obj"


def log_csv(tag=""):
    return f"log{'_' + tag if tag else ''}.csv"


def remove_earlier_run(folder):
    """Remove the files of an earlier run of this program from `folder`; returns how many."""
    removed = 0
    for name in os.listdir(folder):
        path = os.path.join(folder, name)
        if WRITTEN.match(name) and os.path.isfile(path):
            os.remove(path)
            removed += 1
    return removed
