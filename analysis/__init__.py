"""What a run's states say beyond the solver's report, for the tests, the pictures and the window:
diagnostics, stick_slip (the chalk's cycles), log (log.csv's columns), closing (the closing words),
wear (the chalk's mark). No pygame, no files; imports point down to simulator and the energies."""
