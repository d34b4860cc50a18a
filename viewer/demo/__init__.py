"""The live window (`--window`, docs/live-demo.md): live (no pygame), window, newton_view."""
