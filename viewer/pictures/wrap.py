"""Text in rows of a given width, broken where its phrases meet (the window's lines, plots.png's
legends)."""
import re

# where a line breaks, the strongest first: between key hints, after ";", before "(", after ",",
# after ":", " "
BREAKS = ("   ", r"(?<=;) ", r" (?=\()", r"(?<=,) ", r"(?<=:) ", " ")


def phrase_rows(font, text, width, breaks=BREAKS):
    """`text` in rows within `width` px, broken at the strongest of `breaks` needed: no row "p)"."""
    if font.size(text)[0] <= width or not breaks:
        return [text]
    joiner, rows = ("   " if breaks[0] == "   " else " "), []
    for piece in re.split(breaks[0], text):
        if rows and font.size(rows[-1] + joiner + piece)[0] <= width:
            rows[-1] += joiner + piece
        else:
            rows.append(piece)
    return [part for row in rows for part in phrase_rows(font, row, width, breaks[1:])]
