"""Pictures written to files: what a run draws, frame by frame and at its end.

    draw.py         one frame: the slope with distance marks, the bodies, the forces, a legend; PNG
                    data; the drawing helpers (arrowheads, text wrapping, round numbers)
    marks.py        the chalk's mark (analysis.wear) drawn on the board, at true scale and magnified
    frames.py       when each frame is due; writing it (PNG, OBJs, the page's figures)
    plots.py        plots.png: energy budget, contact speeds, Newton iterations (or a comparison of
                    runs); the chalk's tip against the drive, normal force, stick-slip cycles
    summary.py      summary.png: spaced, time-labelled snapshots at a fixed scale
    page.py         index.html: plays the frames from the files, with the plots and a time cursor
    run_pictures.py the pictures written at a run's end: summary.png, plots.png, index.html
"""
