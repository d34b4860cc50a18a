"""The live window (`--window`), for an instructor's demo down to one Newton iteration: live (the
run, its pacing, keys and files; no pygame), window (the loop, the display), newton_view (key n)."""
