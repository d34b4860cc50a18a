"""The pictures of a whole run, written after its steps from what its tracks kept: the chalk's
marks.csv (its mark, viewer.pictures.marks), summary.png, plots.png and, when frames were written, index.html
to play them. viewer.command.run.end writes them however the run ended (done, a failed step, a signal), each
whole as it is done.
"""
from analysis.closing import closing_note
from analysis import wear
from viewer.output import files
from viewer.pictures import draw, page, plots, summary

NAMES = ("summary.png", "plots.png", "index.html")      # in the order written, after the marks


def names(tracks):
    """What `write` writes for these tracks, in order: each chalk's marks.csv, then NAMES."""
    return [files.marks_csv(tr.tag) for tr in tracks if tr.marks is not None] + list(NAMES)


def write(tracks, folder, stride, frames, frame_log, header):
    """Write the pictures of `tracks` into `folder` (files.RunFolder): `header`, the lines of text
    summary.png and the page open with (each then says what the run showed: closing.closing_note);
    `frame_log`, the frames.FrameInfo of each frame written."""
    for tr in tracks:
        if tr.marks is not None:
            folder.write(files.marks_csv(tr.tag), wear.csv_text(tr.marks))
    pygame = draw.load_pygame()
    folder.write("summary.png", draw.png_data(pygame, summary.draw_summary(pygame, tracks, header), exact=True))
    surface, axis = plots.draw_plots(pygame, tracks)
    folder.write("plots.png", draw.png_data(pygame, surface, exact=True))
    if frames:
        fps = 1.0 / (stride * min(tr.scene.h for tr in tracks))
        title = ("Chalk on a board: " if tracks[0].scene.hand is not None else "Square on a slope: ") + \
            ", ".join(tr.label for tr in tracks)
        note = " ".join(header) + "; " + closing_note(tracks)
        folder.write("index.html", page.page_html(title, [tr.label for tr in tracks], frame_log, fps, axis,
                                                  surface.get_width(), note=note, **page.run_figures(tracks)))
