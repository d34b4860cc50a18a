"""The command line and the run, from `python simulator.py [flags]` to its closing line: startup
(before numpy loads), cli (the flags), run (to files; signals; the ending), recording (the scenes
stepped side by side, logged) and progress (what a run says as it goes)."""
