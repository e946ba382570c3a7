"""The frost demo: window, input, simulation thread, rendering, screenshots (GL lives here only)."""
