"""Pictures written to files: what a run draws, frame by frame and at its end.

    draw.py         one frame (the slope, the bodies, the forces, legends), its PNG bytes
    marks.py        the chalk's mark on the board, at true scale and magnified about the tip
    frames.py       when each frame is due, and writing it (PNG, OBJs, the page's figures)
    plots.py        plots.png: the energy budget, contact speeds, Newton iterations; the chalk's
    summary.py      summary.png: spaced, time-labelled snapshots at a fixed scale
    page.py         index.html (from page.html): plays the frames, with the plots and a cursor
    run_pictures.py the pictures written at a run's end
"""
