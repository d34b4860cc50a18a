"""The pictures of a whole run from what its tracks kept, written by viewer.command.run.end however
the run ended: each chalk's marks.csv, summary.png, plots.png, and with frames index.html."""
from analysis import wear
from analysis.closing import closing_note
from scenes import UNITS
from viewer.output import files
from viewer.pictures import draw, page, plots, summary

NAMES = ("summary.png", "plots.png", "index.html")      # in the order written, after the marks
TITLES = {"square": "Square on a slope", "chalk": "Chalk on a board",   # the page's, by --scene
          "tablecloth": "Dish on a tablecloth", **{k: unit.TITLE for k, unit in UNITS.items()}}


def names(tracks):
    """What `write` writes for these tracks, in order: each chalk's marks.csv, then NAMES."""
    return [files.marks_csv(tr.tag) for tr in tracks if tr.marks is not None] + list(NAMES)


def write(tracks, folder, stride, frames, frame_log, header, kind="square"):
    """The pictures of `tracks` into `folder` (files.RunFolder): `header`, the lines summary.png
    and the page open with; `frame_log`, the frames.FrameInfo of each frame written; `kind`, the
    --scene, whose TITLES the page has."""
    for tr in tracks:
        if tr.marks is not None:
            folder.write(files.marks_csv(tr.tag), wear.csv_text(tr.marks))
    pygame = draw.load_pygame()
    surface = summary.draw_summary(pygame, tracks, header)
    folder.write("summary.png", draw.png_data(pygame, surface))
    surface, axis = plots.draw_plots(pygame, tracks)
    folder.write("plots.png", draw.png_data(pygame, surface))
    if frames:
        fps = 1.0 / (stride * min(tr.scene.h for tr in tracks))
        note = " ".join(header) + "; " + closing_note(tracks)
        text = page.page_html(f"{TITLES[kind]}: " + ", ".join(tr.label for tr in tracks),
                              [tr.label for tr in tracks], frame_log, fps, axis,
                              surface.get_width(), note=note, **page.run_figures(tracks))
        folder.write("index.html", text)
