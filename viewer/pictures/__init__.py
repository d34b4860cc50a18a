"""Pictures written to files: frames (draw, marks, frames), plots.png (plots), summary.png
(summary), index.html (page, page.html), and those of a run's end (run_pictures)."""
