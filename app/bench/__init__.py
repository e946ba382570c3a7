"""The benchmarks (`frost bench sim|render|page|serve`, `python -m app.bench.tiles`) and
what only they use: the scripted scribbles, the taps, the pane's and the fern's measures.
They print figures and assert nothing; app.cli runs them, and nothing else of the app
imports them."""
